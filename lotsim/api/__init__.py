"""lotsim as a Python library: the functions ``import lotsim`` offers (``docs/python.md``).

Everything the command line does goes through these, with the same checks and the same
errors (:class:`~lotsim.errors.LotsimError` and its kinds); the CLI only parses its options,
calls them and prints. Scenarios may be given as a :class:`~lotsim.scenario.Scenario`, a
path, or YAML text (a ``str`` holding a line break).

The facade's own functions live in topic modules: :mod:`~lotsim.api.scenarios` (preparing
and validating), :mod:`~lotsim.api.running` (running), :mod:`~lotsim.api.results` (reading,
writing and checking results), :mod:`~lotsim.api.drawing` (pictures, animations, replays),
:mod:`~lotsim.api.maneuvers` (one car, one slot), :mod:`~lotsim.api.layouts` (laying a lot
out on a plot) and :mod:`~lotsim.api.benchmarks`. Beside
them it offers the settings, their choices and the errors the command line needs, from where
they are defined (:data:`EXPORTS` says where each name lives). Each name is imported on first
use, so that ``lotsim --help`` does not load the planners.

Examples
--------
>>> import lotsim
>>> prepared = lotsim.prepare(lotsim.EXAMPLE)
>>> result = lotsim.run(prepared, planner="whca", window=10)
>>> result.metrics()["parked"], lotsim.check(result).ok
(2, True)
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from lotsim import __version__ as __version__  # what lotsim --version says

EXPORTS: dict[str, tuple[str, ...]] = {
    # the facade's own
    "lotsim.api.scenarios": ("EXAMPLE", "FileValidation", "ScenarioLike", "prepare",
                             "prepare_for_drawing", "validate", "validate_files"),
    "lotsim.api.running": ("run",),
    "lotsim.sim.results": ("HOURLY_FROM", "RunResult"),
    "lotsim.io.result": ("result_dict",),
    "lotsim.api.results": ("check", "load_result", "write_result"),
    "lotsim.api.drawing": ("render_gif", "render_html", "render_lot", "render_maneuver",
                           "render_mp4", "render_routes"),
    "lotsim.api.maneuvers": ("car", "maneuver_case", "minslot", "plan_maneuver"),
    "lotsim.api.benchmarks": ("connect_scheduler",),
    "lotsim.api.exports": ("export_commonroad", "export_dxf", "export_openscenario",
                           "export_sumo"),
    "lotsim.api.imports": ("import_dxf", "import_lanelet2", "import_osm"),
    "lotsim.io.imports.report": ("ImportReport", "ImportedLot"),
    "lotsim.io.imports.dxf": ("DxfImportError", "DxfLayers", "DxfPlot"),
    "lotsim.api.layouts": ("layout", "layout_files"),
    "lotsim.design.results": ("Evaluation", "LayoutResult"),
    "lotsim.design.settings": ("LayoutSettings",),
    "lotsim.design.plot": ("PlotSpec",),
    "lotsim.design.plot_yaml": ("read_plot",),
    # scenarios and what they hold
    "lotsim.io.scenario_yaml": ("ScenarioFile", "load_animation", "load_scenario",
                                "read_scenario"),
    "lotsim.scenario": ("AnimationSpec", "GifSettings", "HtmlSettings", "MAX_SIZE", "MIN_SIZE",
                        "VIEWS",
                        "REPLAY_SPEEDS", "Scenario", "size_problem"),
    "lotsim.vehicles.catalogue": ("CATALOGUE",),
    # settings and their choices
    "lotsim.sim.settings": ("ASSIGNMENTS", "GASettings", "PLANNERS", "PRIORITIES",
                            "RunSettings"),
    "lotsim.maneuvers.settings": ("MARGIN", "ManeuverSettings", "MinSlotSettings", "STYLES"),
    "lotsim.roadmap.settings": ("AreaTurnSettings", "MultipointSettings", "RoadmapSettings",
                                "TurnSettings", "TurnaroundSettings"),
    "lotsim.lot.settings": ("LotSettings",),
    "lotsim.maneuvers.slot_table": ("MinSlotTable", "check_slot_width"),
    # prepared lots, runs and their limits
    "lotsim.sim.preparation": ("PreparedLot",),
    "lotsim.roadmap.service_routes": ("RouteReport", "RouteSettings", "plan_routes"),
    "lotsim.sim.maneuver_case": ("ManeuverCase",),
    "lotsim.sim.validation": ("ValidationReport", "id_ranges", "natural", "unusable_text"),
    "lotsim.sim.running": ("collector_tuned", "require_traffic"),
    "lotsim.sim.live": ("Live",),
    "lotsim.sim.execution": ("execute",),
    "lotsim.sim.policies": ("ASK", "Ranked", "SlotRequest"),
    "lotsim.traffic.disturbances": ("Closure", "Disturbances", "Stall", "TakenBay"),
    "lotsim.sim.limits": ("Budget", "Watchdog", "parse_size"),
    "lotsim.verify": ("CheckReport", "Violation"),
    # pictures and plots
    "lotsim.render.lot_image": ("slot_labels_drawn",),
    "lotsim.render.video": ("VideoUnavailable", "require_ffmpeg"),
    "lotsim.render.plots": ("MatplotlibMissing", "plot_minslot", "plot_timeline",
                            "require_matplotlib"),
    "lotsim.io.lot_json": ("LotFormatError",),
    # outputs written as one set
    "lotsim.core.atomic": ("OutputSet",),
    # benchmark suites
    "lotsim.bench": ("DaskMissing", "PLOTS", "SchedulerUnreachable", "hour_rows",
                     "hours_text", "load_suite", "run_suite", "table_text", "write_outputs"),
    # errors
    "lotsim.errors": ("InfeasibleManeuver", "LimitExceeded", "Location", "LotsimError",
                      "DecisionError", "OutputError", "ReplayError", "ResultFormatError",
                      "ScenarioError", "ScenarioErrors", "SettingsError"),
}
"""Module → the public names :mod:`lotsim.api` offers from it."""

EXPORTS_BY_NAME = {name: module for module, names in EXPORTS.items() for name in names}
"""Public name → the module that defines it."""
__all__ = sorted(EXPORTS_BY_NAME)


def __getattr__(name: str) -> Any:
    # looked up anew each time (a module attribute read, once imported), so that the name
    # is always what its module holds now
    module = EXPORTS_BY_NAME.get(name)
    if module is None:
        raise AttributeError(f"module 'lotsim.api' has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # for type checkers and editors: the same names, imported eagerly
    from lotsim.api.benchmarks import connect_scheduler  # noqa: F401
    from lotsim.api.drawing import (  # noqa: F401
        render_gif,
        render_html,
        render_lot,
        render_maneuver,
        render_mp4,
        render_routes,
    )
    from lotsim.api.exports import (  # noqa: F401
        export_commonroad,
        export_dxf,
        export_openscenario,
        export_sumo,
    )
    from lotsim.api.imports import import_dxf, import_lanelet2, import_osm  # noqa: F401
    from lotsim.api.layouts import layout, layout_files  # noqa: F401
    from lotsim.api.maneuvers import car, maneuver_case, minslot, plan_maneuver  # noqa: F401
    from lotsim.api.results import check, load_result, write_result  # noqa: F401
    from lotsim.api.running import run  # noqa: F401
    from lotsim.api.scenarios import (  # noqa: F401
        EXAMPLE,
        FileValidation,
        ScenarioLike,
        prepare,
        prepare_for_drawing,
        validate,
        validate_files,
    )
    from lotsim.bench import (  # noqa: F401
        PLOTS,
        DaskMissing,
        SchedulerUnreachable,
        hour_rows,
        hours_text,
        load_suite,
        run_suite,
        table_text,
        write_outputs,
    )
    from lotsim.core.atomic import OutputSet  # noqa: F401
    from lotsim.design.plot import PlotSpec  # noqa: F401
    from lotsim.design.plot_yaml import read_plot  # noqa: F401
    from lotsim.design.results import Evaluation, LayoutResult  # noqa: F401
    from lotsim.design.settings import LayoutSettings  # noqa: F401
    from lotsim.errors import (  # noqa: F401
        DecisionError,
        InfeasibleManeuver,
        LimitExceeded,
        Location,
        LotsimError,
        OutputError,
        ReplayError,
        ResultFormatError,
        ScenarioError,
        ScenarioErrors,
        SettingsError,
    )
    from lotsim.io.imports.dxf import DxfImportError, DxfLayers, DxfPlot  # noqa: F401
    from lotsim.io.imports.report import ImportedLot, ImportReport  # noqa: F401
    from lotsim.io.lot_json import LotFormatError  # noqa: F401
    from lotsim.io.result import result_dict  # noqa: F401
    from lotsim.io.scenario_yaml import (  # noqa: F401
        ScenarioFile,
        load_animation,
        load_scenario,
        read_scenario,
    )
    from lotsim.lot.settings import LotSettings  # noqa: F401
    from lotsim.maneuvers.settings import (  # noqa: F401
        MARGIN,
        STYLES,
        ManeuverSettings,
        MinSlotSettings,
    )
    from lotsim.maneuvers.slot_table import MinSlotTable, check_slot_width  # noqa: F401
    from lotsim.render.lot_image import slot_labels_drawn  # noqa: F401
    from lotsim.render.plots import (  # noqa: F401
        MatplotlibMissing,
        plot_minslot,
        plot_timeline,
        require_matplotlib,
    )
    from lotsim.render.video import VideoUnavailable, require_ffmpeg  # noqa: F401
    from lotsim.roadmap.service_routes import (  # noqa: F401
        RouteReport,
        RouteSettings,
        plan_routes,
    )
    from lotsim.roadmap.settings import (  # noqa: F401
        AreaTurnSettings,
        MultipointSettings,
        RoadmapSettings,
        TurnaroundSettings,
        TurnSettings,
    )
    from lotsim.scenario import (  # noqa: F401
        MAX_SIZE,
        MIN_SIZE,
        REPLAY_SPEEDS,
        VIEWS,
        AnimationSpec,
        GifSettings,
        HtmlSettings,
        Scenario,
        size_problem,
    )
    from lotsim.sim.execution import execute  # noqa: F401
    from lotsim.sim.limits import Budget, Watchdog, parse_size  # noqa: F401
    from lotsim.sim.live import Live  # noqa: F401
    from lotsim.sim.maneuver_case import ManeuverCase  # noqa: F401
    from lotsim.sim.policies import ASK, Ranked, SlotRequest  # noqa: F401
    from lotsim.sim.preparation import PreparedLot  # noqa: F401
    from lotsim.sim.results import HOURLY_FROM, RunResult  # noqa: F401
    from lotsim.sim.running import collector_tuned, require_traffic  # noqa: F401
    from lotsim.sim.settings import (  # noqa: F401
        ASSIGNMENTS,
        PLANNERS,
        PRIORITIES,
        GASettings,
        RunSettings,
    )
    from lotsim.sim.validation import (  # noqa: F401
        ValidationReport,
        id_ranges,
        natural,
        unusable_text,
    )
    from lotsim.traffic.disturbances import Closure, Disturbances, Stall, TakenBay  # noqa: F401
    from lotsim.vehicles.catalogue import CATALOGUE  # noqa: F401
    from lotsim.verify import CheckReport, Violation  # noqa: F401
