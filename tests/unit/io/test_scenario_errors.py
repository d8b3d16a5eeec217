"""Every bad input is a ScenarioError at the right line and column (as ``lotsim.validate``
raises it; the command line prints it as one line and exits 2: tests/unit/cli/test_commands.py)."""

import textwrap
from pathlib import Path

import pytest

import lotsim
from conftest import position
from lotsim.cli import main

GOOD = """\
name: t
vehicle_types: [valet]
lot:
  boundary: [[0, 0], [60, 0], [60, 30], [0, 30]]
  aisles:
    - id: a
      centerline: [[0, 15], [60, 15]]
      width: 7.0
  rows:
    - aisle: a
      side: left
      kind: perpendicular
      count: 5
      slot_width: 2.5
      slot_length: 5.0
      start: 10.0
    - aisle: a
      side: right
      kind: angled
      angle_deg: 45
      count: 4
      slot_width: 2.5
      slot_length: 5.0
      start: 10.0
      id_prefix: Q
  obstacles:
    - {id: pillar, polygon: [[50, 24], [52, 24], [52, 26], [50, 26]]}
  entrances:
    - {id: in, x: 2.0, y: 13.25, heading_deg: 0}
  exits:
    - {id: out, x: 5.0, y: 16.75, heading_deg: 180}
"""


def refused(tmp_path, text) -> tuple[str, str]:
    """The error ``lotsim.validate`` raises for ``text`` written to a file, and the file."""
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(lotsim.ScenarioError) as err:
        lotsim.validate(path)
    return str(err.value), str(path)


def test_the_good_file_validates():
    assert lotsim.validate(GOOD).warnings == []


# (name, old text, new text, needle marking the reported position, key path, words expected)
CASES = [
    ("unknown key", "      width: 7.0", "      widht: 7.0", "widht", "lot.aisles[0].widht",
     "did you mean 'width'"),
    ("missing key", "      slot_length: 5.0\n      start: 10.0\n    - aisle",
     "      slot_length: 5.0\n    - aisle", "aisle: a\n      side: left", "lot.rows[0]",
     "missing key 'start'"),
    ("wrong type", "      count: 5", "      count: five", "five", "lot.rows[0].count",
     "expected an integer, found string 'five'"),
    ("duplicate key", "      count: 5\n", "      count: 5\n      count: 6\n", "count: 6",
     "lot.rows[0].count", "duplicate key 'count'"),
    ("1e3 read as a string", "      start: 10.0\n    - aisle", "      start: 1e1\n    - aisle",
     "1e1", "lot.rows[0].start", "YAML reads as a string"),
    ("unknown kind", "      kind: perpendicular", "      kind: diagonal", "diagonal",
     "lot.rows[0].kind", "one of perpendicular, parallel, angled"),
    ("negative size", "      slot_width: 2.5\n      slot_length: 5.0\n      start: 10.0\n    - ",
     "      slot_width: -2.5\n      slot_length: 5.0\n      start: 10.0\n    - ", "-2.5",
     "lot.rows[0].slot_width", "positive"),
    ("zero size", "      width: 7.0", "      width: 0", "0\n", "lot.aisles[0].width",
     "positive"),
    ("angle out of range", "angle_deg: 45", "angle_deg: 90", "90", "lot.rows[1].angle_deg",
     "< 90"),
    ("angle on a perpendicular row", "      kind: perpendicular",
     "      kind: perpendicular\n      angle_deg: 60", "angle_deg: |60",
     "lot.rows[0].angle_deg", "angled slots only"),
    ("octal", "      count: 5", "      count: 012", "012", "lot.rows[0].count", "octal"),
    ("yes for a string", "kind: perpendicular", "kind: yes", "yes", "lot.rows[0].kind",
     "boolean"),
    ("NaN", "start: 10.0\n    - aisle", "start: .nan\n    - aisle", ".nan",
     "lot.rows[0].start", "finite"),
    ("unknown aisle", "    - aisle: a\n      side: right", "    - aisle: b\n      side: right",
     "aisle: b", "lot.rows[1]", "found 'b'"),
    ("unknown car", "vehicle_types: [valet]", "vehicle_types: [valett]", "valett",
     "vehicle_types[0]", "did you mean 'valet'"),
]


@pytest.mark.parametrize(("name", "old", "new", "needle", "key", "words"), CASES,
                         ids=[c[0] for c in CASES])
def test_schema_errors_are_located(tmp_path, name, old, new, needle, key, words):
    assert old in GOOD, name
    text = GOOD.replace(old, new, 1)
    err, path = refused(tmp_path, text)
    line, col = position(text, needle)
    assert err.startswith(f"{path}:{line}:{col}: {key}: "), err
    assert words in err and "\n" not in err


def geometry_case(old, new):
    assert old in GOOD
    return GOOD.replace(old, new, 1)


GEOMETRY = [
    ("slots overlap", geometry_case("      start: 10.0\n      id_prefix: Q", "      start: 10.0\n"
     "      id_prefix: Q\n    - {aisle: a, side: right, kind: perpendicular, count: 1, "
     "slot_width: 2.5, slot_length: 5.0, start: 12.0}"), "{aisle: a, side: right, kind: perp",
     "overlaps slot 'Q1'"),
    ("slot on an obstacle", geometry_case("[[50, 24], [52, 24], [52, 26], [50, 26]]",
     "[[10, 20], [12, 20], [12, 22], [10, 22]]"), "aisle: a\n      side: left",
     "overlaps obstacle 'pillar'"),
    ("slot outside the boundary", geometry_case("slot_length: 5.0\n      start: 10.0\n    - ",
     "slot_length: 25.0\n      start: 10.0\n    - "), "aisle: a\n      side: left",
     "outside the lot boundary"),
    ("slot past the aisle end", geometry_case("      count: 5", "      count: 50"),
     "aisle: a\n      side: left", "past the end of aisle 'a'"),
    ("entrance off every aisle", geometry_case("{id: in, x: 2.0, y: 13.25",
     "{id: in, x: 2.0, y: 3.25"), "{id: in", "is on no aisle"),
    ("entrance heading across the lanes", geometry_case("{id: in, x: 2.0, y: 13.25, heading_deg: 0",
     "{id: in, x: 2.0, y: 13.25, heading_deg: 90"), "{id: in", "on no lane driven that way"),
    ("aisle too narrow", geometry_case("      width: 7.0", "      width: 3.0"), "id: a",
     "too narrow"),
    ("slot opens onto no aisle", geometry_case("  obstacles:", "  slots:\n"
     "    - {id: F, kind: perpendicular, width: 2.5, length: 5.0, center: [40, 27],"
     " heading_deg: 90}\n  obstacles:"), "{id: F", "opens onto no aisle"),
    ("occupied slot unknown", GOOD + "  occupied: [Q1, Z9]\n", "Z9", "no slot has"),
]


@pytest.mark.parametrize(("name", "text", "needle", "words"), GEOMETRY,
                         ids=[g[0] for g in GEOMETRY])
def test_geometry_errors_are_located(tmp_path, name, text, needle, words):
    err, path = refused(tmp_path, text)
    line, col = position(text, needle)
    assert err.startswith(f"{path}:{line}:{col}: "), err
    assert words in err, err


CURVY = """\
lot:
  boundary: [[0, 0], [60, 0], [60, 60], [0, 60]]
  aisles:
    - id: bend
      centerline: [[5, 5], [50, 5], [50, 50]]
      width: 7.0
      bend_radius: 3.0
  entrances:
    - {id: in, x: 10, y: 3.25, heading_deg: 0}
"""


def test_curve_too_tight(tmp_path):
    err, path = refused(tmp_path, CURVY)
    line, col = position(CURVY, "id: bend")
    assert err.startswith(f"{path}:{line}:{col}: lot.aisles[0]: ")
    assert "curves too tight" in err


def test_yaml_syntax_error_is_located(tmp_path):
    text = "lot:\n  boundary: [[0, 0], [1, 0]\n  aisles: []\n"
    err, path = refused(tmp_path, text)
    assert err.startswith(f"{path}:3:")
    assert "invalid YAML" in err


def test_missing_file(tmp_path, capsys):
    with pytest.raises(lotsim.ScenarioError, match="nope.yaml: cannot read"):
        lotsim.validate(tmp_path / "nope.yaml")
    # and the command line says so in one line, no traceback
    assert main(["validate", str(tmp_path / "nope.yaml")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lotsim: ") and "cannot read" in err and err.count("\n") == 1


def test_empty_file(tmp_path):
    err, path = refused(tmp_path, "")
    assert err.startswith(f"{path}:1:1: ") and "found an empty file" in err
    # a file of comments only is said to be one
    err, path = refused(tmp_path, "# a lot to come\n\n# its aisles\n")
    assert err.startswith(f"{path}:1:1: ") and "found only comments" in err


def test_unknown_command_and_option_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
    with pytest.raises(SystemExit) as exc:
        main(["validate"])
    assert exc.value.code == 2


def test_position_helper_is_one_based():
    assert position(textwrap.dedent("a: 1\nbb: 22\n"), "22") == (2, 5)


def _tree(node) -> list:
    """A composed YAML node as nested lists: kind, tag, value, where it starts (what errors
    name; end marks are not read, and libyaml ends a last line without a newline elsewhere),
    quoted or not."""
    import yaml

    head = [type(node).__name__, node.tag, node.start_mark.line, node.start_mark.column]
    if isinstance(node, yaml.ScalarNode):
        return [*head, node.value, bool(node.style)]
    if isinstance(node, yaml.SequenceNode):
        return [*head, [_tree(c) for c in node.value]]
    return [*head, [[_tree(k), _tree(v)] for k, v in node.value]]


TRICKY = """\
# a comment
name: 'héllo wörld'   # non-ASCII before later columns
a: &anchor [1, 2.5, "3", {x: ü, y: -4e3}]
b: *anchor
c: |
  two
  lines
d: {e: null, f: ~, g: yes, h: 012, i: .5}
"""


@pytest.mark.parametrize("text", [TRICKY, "a: 1", "[1, [2, [3]]]"], ids=["tricky", "one", "nested"])
def test_fast_composer_builds_the_python_composers_tree(text):
    """libyaml's composer, used when PyYAML has it, gives the pure-Python composer's tree:
    the same tags, values, marks and quoting (what the typed reader and its errors read)."""
    import yaml

    from lotsim.io import yamlnodes

    if yamlnodes._FastLoader is None:
        pytest.skip("PyYAML was built without libyaml")
    slow = _tree(yaml.compose(text, Loader=yamlnodes._ComposeLoader))
    assert _tree(yaml.compose(text, Loader=yamlnodes._FastLoader)) == slow
    assert _tree(yamlnodes.parse_text(text, "x.yaml").node) == slow


def test_shipped_files_compose_the_same_both_ways():
    import yaml

    from lotsim.io import yamlnodes

    if yamlnodes._FastLoader is None:
        pytest.skip("PyYAML was built without libyaml")
    root = Path(lotsim.__file__).resolve().parents[1]
    files = sorted(root.glob("scenarios/**/*.yaml"))
    assert len(files) >= 10
    for f in files:
        text = f.read_text()
        assert (_tree(yaml.compose(text, Loader=yamlnodes._FastLoader))
                == _tree(yaml.compose(text, Loader=yamlnodes._ComposeLoader))), f


@pytest.mark.parametrize("text", [
    "lot:\n  boundary: [[0, 0], [1, 0]\n  aisles: []\n",  # unclosed flow sequence
    "a: 1\n b: 2\n",  # bad indentation
    "a: 'open\n",  # unterminated quote
    "a: \x07\n",  # a character YAML does not allow
    "a: *nowhere\n",  # unknown alias
])
def test_unreadable_yaml_is_reported_as_the_python_composer_reports_it(text):
    """What libyaml cannot read is read again by the pure-Python composer, whose error
    (message and place) is the one reported, whichever composer PyYAML has."""
    import yaml

    from lotsim.io import yamlnodes

    with pytest.raises(lotsim.ScenarioError) as got:
        yamlnodes.parse_text(text, "x.yaml")
    with pytest.raises(lotsim.ScenarioError) as want:
        fast, yamlnodes._FastLoader = yamlnodes._FastLoader, None
        try:
            yamlnodes.parse_text(text, "x.yaml")
        finally:
            yamlnodes._FastLoader = fast
    assert str(got.value) == str(want.value)
    assert "x.yaml:" in str(got.value)
    with pytest.raises(yaml.YAMLError):
        yaml.compose(text, Loader=yamlnodes._ComposeLoader)


TWO_PROBLEMS = """\
name: two-problems
vehicle_types: [valet, {name: van, width: 2.0, front: 4.2, rear: 1.0, wheelbase: 3.3}]
lot:
  boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [40, 10]], width: 7.0}
  rows:
    - {aisle: main, side: left, kind: perpendicular, count: 5, slot_widht: 2.5,
       slot_length: 5.5, start: 8.0}
    - {aisle: main, side: right, kind: perpendicular, count: 5, slot_width: 2.5,
       slot_length: 5.5, start: 8.0}
  entrances:
    - {id: in, x: 3.0, y: 8.25, heading_deg: 0}
traffic:
  vehicles:
    - {id: a, arrival: 0, type: van, entrance: in}
  stream: {count: 5, rate_per_hour: -60}
"""


def test_validate_reports_every_independent_problem_in_file_order(tmp_path, capsys):
    """A misspelt key in a row and a negative rate in the stream: both, each located, and
    nothing about the traffic's type or entrance, which the broken parts still declare."""
    path = tmp_path / "two.yaml"
    path.write_text(TWO_PROBLEMS)
    assert main(["validate", str(path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 3, lines  # the van misses max_steer_deg; the row; the stream
    where = [tuple(map(int, ln.split(":")[2:4])) for ln in lines]
    assert where == [position(TWO_PROBLEMS, "|{name: van"),
                     position(TWO_PROBLEMS, "|slot_widht"),
                     position(TWO_PROBLEMS, "rate_per_hour: |-60")]
    assert all(ln.startswith(f"lotsim: {path}:") for ln in lines)
    assert "slot_widht" in lines[1] and "rate_per_hour" in lines[2]


UNITS = """\
vehicle_types:
  - {name: van, width: 2.0, front: 4.2, rear: 1.0, wheelbase: 3.3, max_steer_deg: STEER}
lot:
  boundary: [[0, 0], [40, 0], [40, 20], [0, 20]]
  aisles:
    - {id: main, centerline: [[0, 10], [40, 10]], width: WIDTH, direction: one-way}
  rows:
    - {aisle: main, side: left, kind: angled, angle_deg: ANGLE, count: 4, slot_width: 2.5,
       slot_length: 5.0, start: 4}
  entrances: [{id: in, x: 2, y: 10, heading_deg: 0}]
"""


@pytest.mark.parametrize("values, key, words", [
    ({"ANGLE": "0.785"}, "angle_deg: |0.785", "looks like radians (45.0°): write 45"),
    ({"STEER": "0.52"}, "max_steer_deg: |0.52", "looks like radians (29.8°): write 30"),
    ({"WIDTH": "7000"}, "width: |7000", "in millimetres? lotsim's lengths are metres: "
                                        "7000 mm is 7 m"),
])
def test_a_value_plausible_in_another_unit_says_so(values, key, words):
    """Radians for degrees and millimetres for metres are refused where they are written,
    saying which unit the value looks like."""
    text = UNITS
    for k, v in {"STEER": "30", "WIDTH": "6.0", "ANGLE": "45", **values}.items():
        text = text.replace(k, v)
    with pytest.raises(lotsim.ScenarioError) as err:
        lotsim.validate(text)
    assert (err.value.where.line, err.value.where.col) == position(text, key)
    assert words in err.value.message
