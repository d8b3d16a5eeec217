"""CommonRoad export: commonroad-io reads the files back and its schemas accept them; every
trajectory agrees with result.json within the stated error; the KS model of
commonroad-vehicle-models, integrated step by step, drives every trajectory within the
steering-rate limit; a planted steering jump is caught."""

from __future__ import annotations

import copy
import datetime
import math
from pathlib import Path

import numpy as np
import pytest

from export_runs import need, result_path, run_params
from lotsim.api import load_result
from lotsim.io.export.commonroad import COMMONROAD_VEHICLES, DT, trips
from lotsim.io.export.tracks import resample, tracks

POSITION_ERROR = 0.01
"""Stated error of the resampled tracks: every lotsim sample lies within 1 cm [m] ..."""
HEADING_ERROR = 0.002
"""... and 2 mrad [rad] of the exported track (docs/export.md)."""
KS_POSITION = 0.005
"""The KS model, integrated over one step from a state with the step's constant steering
rate and acceleration, ends within 5 mm [m] ..."""
KS_HEADING = 0.002
"""... and 2 mrad [rad] of the next state."""
SUBSTEPS = 2
"""Runge-Kutta steps per state step (4th order: at 0.05 s its own error is below 1 µm)."""


@pytest.fixture(scope="module", params=run_params())
def exported(request, tmp_path_factory):
    need("commonroad")
    import lotsim

    doc = load_result(result_path(request.param))
    folder = tmp_path_factory.mktemp(f"cr-{request.param}")
    info = lotsim.export_commonroad(doc, folder)
    return doc, info, read_back(info)


def read_back(info):
    """Each trip's scenario, planning problems and solution, read by commonroad-io."""
    from commonroad.common.file_reader import CommonRoadFileReader
    from commonroad.common.solution import CommonRoadSolutionReader

    out = []
    for trip, scenario_file, solution_file in info.files:
        scenario, problems = CommonRoadFileReader(filename_2020a=str(scenario_file)).open()
        out.append((trip, scenario, problems, CommonRoadSolutionReader.open(str(solution_file))))
    return out


def schema_errors(path: Path, xsd: str) -> list[str]:
    import commonroad
    from lxml import etree

    folder = Path(commonroad.__file__).parent / "common" / "xml_definition_files"
    schema = etree.XMLSchema(etree.parse(str(folder / xsd)))
    ok = schema.validate(etree.parse(str(path)))
    return [] if ok else [str(e) for e in schema.error_log][:5]


def test_commonroad_reads_the_files_back_and_its_schemas_accept_them(exported):
    doc, info, solved = exported
    assert [t for t, _, _ in info.files] == [t for t, _, _ in trips(doc)]
    for _, scenario_file, solution_file in info.files:
        assert schema_errors(scenario_file, "XML_commonRoad_XSD.xsd") == []
        assert schema_errors(solution_file, "CommonRoadSolution_schema.xsd") == []
    parked = len(doc["lot"]["parked"])
    for trip, scenario, problems, solution in solved:
        assert math.isclose(scenario.dt, DT)
        assert list(problems.planning_problem_dict) == [trip.id]
        (pps,) = solution.planning_problem_solutions
        assert pps.vehicle_model.name == "KS" and pps.planning_problem_id == trip.id
        assert len(pps.trajectory.state_list) == trip.last - trip.first + 1
        # walls, islands and the boundary as static obstacles, parked cars among them
        kinds = [o.obstacle_type.value for o in scenario.static_obstacles]
        assert kinds.count("roadBoundary") >= 4 and kinds.count("parkedVehicle") >= parked
        # the lanes and every slot as lanelets
        types = [next(iter(ll.lanelet_type)).value for ll in scenario.lanelet_network.lanelets]
        assert types.count("parking") == len(doc["lot"]["slots"])
        if trip.kind == "in":  # the goal: the car's own slot, reached at the end
            goal = problems.planning_problem_dict[trip.id].goal
            assert goal.is_reached(pps.trajectory.state_list[-1])


def states_of(solution) -> dict[int, dict[str, np.ndarray]]:
    out = {}
    for s in solution.planning_problem_solutions:
        st = s.trajectory.state_list
        out[s.planning_problem_id] = {
            "vehicle": s.vehicle_type.value,
            "k": np.array([x.time_step for x in st]),
            "x": np.array([x.position[0] for x in st]),
            "y": np.array([x.position[1] for x in st]),
            "psi": np.array([x.orientation for x in st]),
            "v": np.array([x.velocity for x in st]),
            "delta": np.array([x.steering_angle for x in st]),
        }
    return out


def rear_axle(s: dict) -> tuple[np.ndarray, np.ndarray]:
    """The KS model's rear axle: the centre moved back by the vehicle's ``b``, as
    CommonRoad's checker does."""
    b = COMMONROAD_VEHICLES[s["vehicle"]][2]
    return s["x"] - b * np.cos(s["psi"]), s["y"] - b * np.sin(s["psi"])


def agreement(doc: dict, solved) -> tuple[float, float]:
    """Largest distance [m] and heading difference [rad] between a lotsim sample and the
    exported track at the sample's time (linear between states), over every trip."""
    by_id = {tr.id: tr for tr in tracks(doc)}
    worst_p = worst_h = 0.0
    for trip, _, _, solution in solved:
        s, tr = states_of(solution)[trip.id], by_id[trip.vehicle]
        t = (s["k"] + trip.first) * DT
        rx, ry = rear_axle(s)
        keep = (tr.t >= t[0]) & (tr.t <= t[-1])
        ts = tr.t[keep]
        dx = np.interp(ts, t, rx) - tr.x[keep]
        dy = np.interp(ts, t, ry) - tr.y[keep]
        dh = np.interp(ts, t, s["psi"]) - tr.theta[keep]
        worst_p = max(worst_p, float(np.hypot(dx, dy).max()))
        worst_h = max(worst_h, float(np.abs((dh + np.pi) % (2 * np.pi) - np.pi).max()))
        # and at the states' own times, the interpolation of the samples, to the float
        r = resample(tr, t)
        assert np.hypot(rx - r["x"], ry - r["y"]).max() < 1e-6
    return worst_p, worst_h


def test_every_trajectory_agrees_with_the_result_within_the_stated_error(exported):
    doc, info, solved = exported
    p, h = agreement(doc, solved)
    assert p <= POSITION_ERROR and h <= HEADING_ERROR, (p, h)
    assert info.position_error <= POSITION_ERROR and info.heading_error <= HEADING_ERROR


def ks_violations(doc: dict, solved, *, limit: int = 5) -> list[str]:
    """Integrate the KS model of commonroad-vehicle-models over every step of every
    trajectory, with the step's steering rate and acceleration held constant (RK4, :data:`SUBSTEPS`
    sub-steps); list the steps whose steering rate exceeds the type's limit (lotsim's,
    in CommonRoad's steering angle) or whose end misses the next state."""
    need("vehiclemodels")
    from vehiclemodels import parameters_vehicle1, parameters_vehicle2, parameters_vehicle3
    from vehiclemodels.vehicle_dynamics_ks import vehicle_dynamics_ks

    params = {
        1: parameters_vehicle1.parameters_vehicle1,
        2: parameters_vehicle2.parameters_vehicle2,
        3: parameters_vehicle3.parameters_vehicle3,
    }
    types = {tr.id: tr.shape for tr in tracks(doc)}
    out = []
    for trip, _, _, solution in solved:
        s, shape = states_of(solution)[trip.id], types[trip.vehicle]
        p = params[s["vehicle"]]()
        ratio = (p.a + p.b) / shape.wheelbase
        # the steering rate lotsim's limit allows, in CommonRoad's angle (its largest)
        rate = shape.max_steer_rate * max(
            ratio / (math.cos(f) ** 2 + ratio**2 * math.sin(f) ** 2) for f in (0.0, shape.max_steer)
        )
        p.steering.v_max, p.steering.v_min = rate + 1e-6, -rate - 1e-6
        rx, ry = rear_axle(s)
        x = np.stack([rx, ry, s["delta"], s["v"], s["psi"]], axis=1)
        for k in range(len(x) - 1):
            u = [(x[k + 1, 2] - x[k, 2]) / DT, (x[k + 1, 3] - x[k, 3]) / DT]
            if abs(u[0]) > rate + 1e-6:
                out.append(
                    f"problem {trip.id} step {s['k'][k]}: steering rate "
                    f"{u[0]:.3f} rad/s > {rate:.3f}"
                )
            else:
                h, z = DT / SUBSTEPS, x[k].copy()
                for _ in range(SUBSTEPS):
                    k1 = np.array(vehicle_dynamics_ks(z, u, p))
                    k2 = np.array(vehicle_dynamics_ks(z + h / 2 * k1, u, p))
                    k3 = np.array(vehicle_dynamics_ks(z + h / 2 * k2, u, p))
                    k4 = np.array(vehicle_dynamics_ks(z + h * k3, u, p))
                    z = z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
                dp = math.hypot(z[0] - x[k + 1, 0], z[1] - x[k + 1, 1])
                dh = abs(z[4] - x[k + 1, 4])
                if dp > KS_POSITION or dh > KS_HEADING:
                    out.append(
                        f"problem {trip.id} step {s['k'][k]}: the KS model ends "
                        f"{dp * 1000:.1f} mm, {dh * 1000:.2f} mrad off"
                    )
            if len(out) >= limit:
                return out
    return out


def test_the_ks_model_drives_every_trajectory_within_its_steering_rate(exported):
    doc, _, solved = exported
    assert ks_violations(doc, solved) == []


def test_a_planted_steering_jump_is_caught(exported):
    doc, _, solved = exported
    trip, scenario, problems, solution = solved[1]
    bad = copy.deepcopy(solution)
    (pps,) = bad.planning_problem_solutions
    st = pps.trajectory.state_list
    k = len(st) // 2
    for s in st[k:]:  # from one step on, the wheels stand 0.1 rad further left
        s.steering_angle += 0.1
    found = ks_violations(doc, [(trip, scenario, problems, bad)])
    assert found and f"problem {trip.id} step {st[k - 1].time_step}:" in found[0], found


@pytest.mark.slow
def test_the_same_result_gives_the_same_files_whatever_the_day(exported, tmp_path):
    # CommonRoad's writer stamps the day it writes; the export fixes the date in the header
    import lotsim
    from lotsim.io.export.commonroad import FILE_DATE

    doc, info, _ = exported
    again = lotsim.export_commonroad(doc, tmp_path / "again")
    for (_, a, sa), (_, b, sb) in zip(info.files, again.files, strict=True):
        assert Path(a).read_bytes() == Path(b).read_bytes()
        assert Path(sa).read_bytes() == Path(sb).read_bytes()
    header = Path(info.files[0][1]).read_text()[:400]
    assert f'date="{FILE_DATE}"' in header and str(datetime.date.today()) != FILE_DATE
