"""lotsim: plan many car-like vehicles in a parking lot.

The pipeline runs one way: a scenario YAML is loaded and validated into frozen
specs (:mod:`lotsim.io`), the lot layout is built into slot polygons and lanes
(:mod:`lotsim.lot`), and the lanes into a drivable :class:`networkx.DiGraph`
(:mod:`lotsim.roadmap`) that vehicles (:mod:`lotsim.vehicles`) travel.

As a library (``docs/python.md``)::

    import lotsim
    prepared = lotsim.prepare("scenarios/quickstart.yaml")
    result = lotsim.run(prepared, planner="whca", window=10)
    lotsim.check(result).ok

The names below are imported on first use (:mod:`lotsim.api`, :mod:`lotsim.sim.settings`,
:mod:`lotsim.errors`), so ``import lotsim`` and ``lotsim --help`` stay quick.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

_EXPORTS = {
    "lotsim.api": ("EXAMPLE", "MinSlotTable", "RunResult", "car", "check", "load_animation",
                   "load_scenario", "minslot", "plan_maneuver", "prepare", "render_gif",
                   "render_html", "render_lot", "render_mp4", "run", "validate",
                   "validate_files",
                   "export_commonroad", "export_sumo", "export_openscenario", "export_dxf",
                   "result_dict", "write_result", "load_result", "import_osm",
                   "import_lanelet2", "import_dxf", "layout",
                   "LayoutSettings", "read_plot"),
    "lotsim.io.imports.dxf": ("DxfLayers",),
    "lotsim.sim.preparation": ("PreparedLot",),
    "lotsim.sim.live": ("Live",),
    "lotsim.sim.execution": ("execute",),
    "lotsim.sim.policies": ("ASK", "Ranked", "SlotRequest"),
    "lotsim.traffic.disturbances": ("Closure", "Disturbances", "Stall", "TakenBay"),
    "lotsim.sim.validation": ("ValidationReport",),
    "lotsim.verify": ("CheckReport", "Violation"),
    "lotsim.scenario": ("AnimationSpec", "GifSettings", "HtmlSettings", "Scenario"),
    "lotsim.sim.settings": ("GASettings", "RunSettings", "RunTuning"),
    "lotsim.maneuvers.settings": ("ManeuverSettings", "MinSlotSettings"),
    "lotsim.roadmap.settings": ("AreaTurnSettings", "MultipointSettings", "RoadmapSettings",
                                "TurnSettings", "TurnaroundSettings"),
    "lotsim.lot.settings": ("LotSettings",),
    "lotsim.errors": ("InfeasibleManeuver", "LimitExceeded", "Location", "LotsimError",
                      "DecisionError", "OutputError", "ReplayError", "ResultFormatError",
                      "ScenarioError", "ScenarioErrors", "SettingsError"),
}
_WHERE = {name: module for module, names in _EXPORTS.items() for name in names}
__all__ = sorted(_WHERE)


def __getattr__(name: str) -> Any:
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module 'lotsim' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # found once; later lookups do not come here
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


def _show_in_notebooks() -> None:
    """In IPython, let runs, prepared lots and validation reports show themselves
    (:mod:`lotsim.api.notebook`); nothing elsewhere."""
    import sys

    if "IPython" in sys.modules:
        from lotsim.api.notebook import register_if_interactive

        register_if_interactive()


_show_in_notebooks()


if TYPE_CHECKING:  # for type checkers and editors: the same names, imported eagerly
    from lotsim.api import (  # noqa: F401
        EXAMPLE,
        LayoutSettings,
        MinSlotTable,
        RunResult,
        car,
        check,
        export_commonroad,
        export_dxf,
        export_openscenario,
        export_sumo,
        import_dxf,
        import_lanelet2,
        import_osm,
        layout,
        load_animation,
        load_result,
        load_scenario,
        minslot,
        plan_maneuver,
        prepare,
        read_plot,
        render_gif,
        render_html,
        render_lot,
        render_mp4,
        result_dict,
        run,
        validate,
        validate_files,
        write_result,
    )
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
    from lotsim.io.imports.dxf import DxfLayers  # noqa: F401
    from lotsim.lot.settings import LotSettings  # noqa: F401
    from lotsim.maneuvers.settings import ManeuverSettings, MinSlotSettings  # noqa: F401
    from lotsim.roadmap.settings import (  # noqa: F401
        AreaTurnSettings,
        MultipointSettings,
        RoadmapSettings,
        TurnaroundSettings,
        TurnSettings,
    )
    from lotsim.scenario import AnimationSpec, GifSettings, HtmlSettings, Scenario  # noqa: F401
    from lotsim.sim.execution import execute  # noqa: F401
    from lotsim.sim.live import Live  # noqa: F401
    from lotsim.sim.policies import ASK, Ranked, SlotRequest  # noqa: F401
    from lotsim.sim.preparation import PreparedLot  # noqa: F401
    from lotsim.sim.settings import GASettings, RunSettings, RunTuning  # noqa: F401
    from lotsim.sim.validation import ValidationReport  # noqa: F401
    from lotsim.traffic.disturbances import Closure, Disturbances, Stall, TakenBay  # noqa: F401
    from lotsim.verify import CheckReport, Violation  # noqa: F401
