"""The CAD layers lotsim writes a lot on and reads a plot from (``docs/export.md``,
``docs/import.md``): one closed table, :data:`LAYERS`, and the bay layer of each use of bay,
:data:`BAY_LAYERS`.

Names follow the US National CAD Standard's layer format (NCS, the AIA CAD Layer
Guidelines): a discipline (``C``, civil), a four-letter major group (``PRKG``, parking
lots; ``BLDG``, buildings) and optional four-letter minor groups. Each entry says whether
the name is the standard's own or lotsim's (a minor group of lotsim's choosing under the
standard's major group, as the standard lets a user define minor groups).

Examples
--------
>>> LAYER_NAMES["stripe"], bay_layer("standard"), bay_layer("van_accessible")
('C-PRKG-STRP', 'C-PRKG', 'C-PRKG-ACCV')
>>> bay_layer("valet")
Traceback (most recent call last):
...
KeyError: "no bay layer for the use 'valet': expected one of standard, compact, accessible, \
van_accessible, ev, motorcycle"
"""

from __future__ import annotations

from dataclasses import dataclass

from lotsim.lot.uses import STANDARD, USES


@dataclass(frozen=True, slots=True)
class CadLayer:
    """One layer of a lot drawn for CAD.

    Attributes
    ----------
    key : str
        What lotsim calls what the layer holds.
    name : str
        The layer's name.
    origin : str
        ``"NCS"``: a name of the standard's own; ``"lotsim"``: lotsim's minor group under
        the standard's major group.
    holds : str
        What is drawn on it, and as which entities.
    color : int
        AutoCAD colour index of the layer (entities are drawn ``BYLAYER``).
    linetype : str
        The layer's linetype (``Continuous``, ``CENTER``, ``DASHED``).
    """

    key: str
    name: str
    origin: str
    holds: str
    color: int = 7
    linetype: str = "Continuous"


_BAY_LAYER_NAMES = {STANDARD: ("C-PRKG", "NCS"), "compact": ("C-PRKG-CMPT", "lotsim"),
                    "accessible": ("C-PRKG-ACCS", "lotsim"),
                    "van_accessible": ("C-PRKG-ACCV", "lotsim"),
                    "ev": ("C-PRKG-EVCH", "lotsim"), "motorcycle": ("C-PRKG-MCYC", "lotsim")}

BAY_USES: tuple[tuple[str, str, str], ...] = tuple(
    (use, *_BAY_LAYER_NAMES[use]) for use in USES)
"""Each use of bay (:data:`lotsim.lot.uses.USES`, in its order) → the layer its bays are
drawn on, and whose name that is."""

BAY_LAYERS: dict[str, str] = {use: name for use, name, _ in BAY_USES}
"""Use of bay → its layer (:data:`BAY_USES`)."""

_BAY_COLORS = {STANDARD: 7, "compact": 4, "accessible": 5, "van_accessible": 5, "ev": 3,
               "motorcycle": 6}

LAYERS: tuple[CadLayer, ...] = (
    CadLayer("boundary", "C-PRKG-OTLN", "lotsim",
             "the lot's boundary (a plot's outline), one closed LWPOLYLINE", 7),
    CadLayer("pavement", "C-PRKG-PVMT", "lotsim",
             "what is paved, where the lot is not paved wall to wall: closed LWPOLYLINEs", 8),
    CadLayer("centreline", "C-PRKG-CNTR", "lotsim",
             "each aisle's centreline as given, an LWPOLYLINE", 1, "CENTER"),
    CadLayer("aisle_edge", "C-PRKG-EDGE", "lotsim",
             "the aisles' pavement edges (the outline of all aisles together): closed "
             "LWPOLYLINEs", 8),
    CadLayer("arrow", "C-PRKG-ARRW", "lotsim",
             "each lane's direction arrows: closed LWPOLYLINEs filled by a solid HATCH", 8),
    *(CadLayer(f"bay:{use}", name, origin,
               f"each bay of {USES[use].label} use, a closed LWPOLYLINE of its four "
               f"corners", _BAY_COLORS[use])
      for use, name, origin in BAY_USES),
    CadLayer("access_aisle", "C-PRKG-ACCA", "lotsim",
             "the access aisles beside accessible bays: closed LWPOLYLINEs hatched by a "
             "HATCH of parallel lines", 5),
    CadLayer("stripe", "C-PRKG-STRP", "NCS",
             "the painted lines of the bays (every side but the entry, each drawn once): "
             "LINEs", 7),
    CadLayer("bay_number", "C-PRKG-IDEN", "NCS",
             "each bay's id, a TEXT at its centre along its length", 7),
    CadLayer("taken", "C-PRKG-TAKN", "lotsim",
             "bays taken at start: an LWPOLYLINE inside the bay and its two diagonals "
             "(LINEs)", 30),
    CadLayer("island", "C-PRKG-ISLD", "lotsim",
             "islands and no-go zones: closed LWPOLYLINEs, each id a TEXT inside", 3),
    CadLayer("obstacle", "C-PRKG-OBST", "lotsim",
             "obstacles (buildings, pillars, kiosks): closed LWPOLYLINEs, each id a TEXT "
             "inside", 9),
    CadLayer("wall", "C-PRKG-WALL", "lotsim",
             "walls: closed LWPOLYLINEs, each id a TEXT inside", 252),
    CadLayer("bump", "C-PRKG-BUMP", "lotsim",
             "speed bumps: an LWPOLYLINE along each and a TEXT of its limit", 30, "DASHED"),
    CadLayer("speed_zone", "C-PRKG-SPED", "lotsim",
             "speed zones: closed LWPOLYLINEs and a TEXT of each limit", 6, "DASHED"),
    CadLayer("entrance", "C-PRKG-ENTR", "lotsim",
             "each entrance: a closed LWPOLYLINE arrow at its pose, the way cars go, and "
             "its id as TEXT", 3),
    CadLayer("exit", "C-PRKG-EXIT", "lotsim",
             "each exit, drawn as an entrance is", 1),
    CadLayer("gate", "C-PRKG-GATE", "lotsim",
             "gates: a POINT where a road meets the boundary, and its name as TEXT (written "
             "where the lanes of the entrances and exits cross the boundary; read as a "
             "plot's gates)", 4),
    CadLayer("route_envelope", "C-PRKG-ENVL", "lotsim",
             "each service route's swept envelope (the scenario's routes): closed "
             "LWPOLYLINEs, its exterior and any holes, and the route's id as TEXT inside", 6),
    CadLayer("route_path", "C-PRKG-ROUT", "lotsim",
             "each service route's path, the line of the vehicle's rear-axle centre: an "
             "LWPOLYLINE per stroke, a reverse stroke DASHED", 4),
    CadLayer("building_entrance", "C-BLDG-ENTR", "lotsim",
             "building entrances: POINTs (read into a plot; a lot has none to write)", 5),
)
"""Every layer lotsim writes or reads, in the order they are written."""

LAYER_NAMES: dict[str, str] = {layer.key: layer.name for layer in LAYERS}
"""What a layer holds (:attr:`CadLayer.key`) → its name."""


def bay_layer(use: str) -> str:
    """The layer a bay of ``use`` is drawn on (:data:`BAY_USES`); an unknown use is a
    ``KeyError`` naming those there are."""
    try:
        return BAY_LAYERS[use]
    except KeyError:
        raise KeyError(f"no bay layer for the use {use!r}: expected one of "
                       f"{', '.join(BAY_LAYERS)}") from None
