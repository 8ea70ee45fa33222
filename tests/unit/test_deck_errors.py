"""Deck errors: pydantic failures become one-line, located DeckErrors; malformed decks exit 65.

The converter tests use small models of their own; the bad decks in tests/data/bad_decks use the
real schema. Each bad deck's first line reads ``# expect-line: N path: P text: T`` (path and text
optional): the error must be at line N, at path P, and contain T.
"""
from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path
from typing import Annotated, Literal, Union

import pytest
from pydantic import BaseModel, ConfigDict, Field, model_validator

from sphfem_cli.deck import DeckError, DeckErrors, load_deck, validate_model
from sphfem_cli.deck.loader import loads

BAD_DECKS = sorted((Path(__file__).parents[1] / "data" / "bad_decks").glob("*.yaml"))
HEADER = re.compile(r"# expect-line: (\d+)(?: path: (\S+))?(?: text: (.*))?$")
ONE_LINE = re.compile(r"^(?P<file>.+):(?P<line>\d+):(?P<col>\d+): (?P<path>\S+): (?P<msg>.+)$")


class Base(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


class Elastic(Base):
    type: Literal["elastic"]
    density: float = Field(gt=0)
    nu: float = Field(0.3, ge=0, lt=0.5)


class Fluid(Base):
    type: Literal["fluid"]
    density: float = Field(gt=0)
    eos: str


Material = Annotated[Union[Elastic, Fluid], Field(discriminator="type")]


class Box(Base):
    min: tuple[float, float]
    size: list[float] = Field(min_length=2, max_length=3)


class Part(Base):
    material: str
    box: Box | None = None
    scale: float | list[float] = 1.0
    count: int = 1
    tags: list[str] = Field(default_factory=list, min_length=0, max_length=2)

    @model_validator(mode="after")
    def _count(self) -> "Part":
        if self.count == 13:
            raise ValueError("@count: unlucky number")
        if self.count == 14:
            raise ValueError("Count 14 is not allowed")
        if self.count == 15:
            raise ValueError("@: the whole part is wrong")
        if self.count == 16:
            raise ValueError("@top: absolute path")
        return self


class Top(Base):
    top: str = "x"
    materials: dict[str, Material]
    parts: dict[str, Part] = Field(default_factory=dict)
    items: list[Part] = Field(default_factory=list)
    axes: dict[Literal["x", "y"], float] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _references(self) -> "Top":
        known = ", ".join(sorted(self.materials))
        for name, part in self.parts.items():
            if part.material not in self.materials:
                raise ValueError(f"@parts.{name}.material: unknown material '{part.material}' "
                                 f"(known: {known})")
        for i, part in enumerate(self.items):
            if part.material not in self.materials:
                raise ValueError(f"@items.{i}.material: unknown material '{part.material}'")
        return self


MATS = "materials:\n  steel: {type: elastic, density: 7850.0}\n"


def check(text: str) -> DeckErrors:
    data, positions = loads(text, "t.yaml")
    with pytest.raises(DeckError) as info:
        validate_model(Top, data, positions, "t.yaml")
    assert isinstance(info.value, DeckErrors)
    assert ONE_LINE.match(str(info.value)), str(info.value)
    return info.value


def where(err: DeckError) -> tuple[int, int, str]:
    return err.line, err.col, err.path


def test_valid_data_passes() -> None:
    text = MATS + "parts:\n  p: {material: steel, box: {min: [0, 1], size: [1, 2]}}\n"
    data, positions = loads(text)
    top = validate_model(Top, data, positions, "t.yaml")
    assert top.parts["p"].box.min == (0.0, 1.0)


def test_missing_key_points_at_its_mapping() -> None:
    err = check("materials:\n  steel:\n    type: elastic\n")
    assert where(err) == (2, 3, "materials.steel")
    assert err.message == "missing required key 'density'"


def test_missing_top_level_key() -> None:
    err = check("\n\ntop: y\n")
    assert where(err) == (3, 1, "") and err.message == "missing required key 'materials'"
    assert str(err) == "t.yaml:3:1: <root>: missing required key 'materials'"


def test_unknown_key_with_suggestion_and_allowed_list() -> None:
    err = check("materials:\n  steel: {type: elastic, density: 1.0, densty: 2.0}\n")
    assert where(err) == (2, 40, "materials.steel.densty")
    assert err.message == ("unknown key 'densty' (did you mean 'density'?; "
                           "allowed: type, density, nu)")


def test_a_misspelt_key_is_reported_before_the_missing_one() -> None:
    err = check("materials:\n  steel:\n    type: elastic\n    dens: 2.0\n")
    assert err.errors[0].path == "materials.steel.dens"
    assert err.errors[1].message == "missing required key 'density'"


def test_discriminator_tag_is_dropped_from_the_path() -> None:
    err = check("materials:\n  steel: {type: elastic, density: -1.0}\n")
    assert where(err) == (2, 35, "materials.steel.density")
    assert err.message == "must be > 0, got -1.0"


def test_unknown_union_tag() -> None:
    err = check("materials:\n  steel: {type: elastik, density: 1.0}\n")
    assert where(err) == (2, 17, "materials.steel.type")
    assert err.message == ("unknown type 'elastik' (did you mean 'elastic'?; "
                           "expected one of: elastic, fluid)")


def test_missing_union_tag() -> None:
    err = check("materials:\n  steel: {density: 1.0}\n")
    assert where(err) == (2, 3, "materials.steel")
    assert err.message == "missing required key 'type' (one of: elastic, fluid)"


@pytest.mark.parametrize("value, message", [
    ("abc", "expected a number, got 'abc' (str)"),
    ("'1.0'", "expected a number, got '1.0' (str)"),
    ("true", "expected a number, got true (bool)"),
    ("[1.0]", "expected a number, got a list"),
    ("~", "expected a number, got null"),
])
def test_wrong_type_points_at_the_value(value: str, message: str) -> None:
    err = check(f"materials:\n  steel: {{type: elastic, density: {value}}}\n")
    col = 26 if value.startswith("[") else 35
    assert where(err) == (2, col, "materials.steel.density") and err.message == message


def test_list_where_a_mapping_is_expected_points_at_the_key() -> None:
    err = check("materials:\n  - steel\n")
    assert where(err) == (1, 1, "materials") and err.message == "expected a mapping, got a list"


@pytest.mark.parametrize("value, message", [
    ("0.5", "must be < 0.5, got 0.5"), ("-0.1", "must be >= 0, got -0.1"),
])
def test_ranges(value: str, message: str) -> None:
    err = check(f"materials:\n  steel: {{type: elastic, density: 1.0, nu: {value}}}\n")
    assert err.path == "materials.steel.nu" and err.message == message


@pytest.mark.parametrize("field, message", [
    ("min: [1, 2, 3]", "expected 2 values, got 3"),
    ("min: [1]", "expected 2 values, got 1"),
    ("size: [1]", "expected at least 2 values, got 1"),
    ("size: [1, 2, 3, 4]", "expected at most 3 values, got 4"),
])
def test_lengths(field: str, message: str) -> None:
    defaults = {"min": "min: [0, 0]", "size": "size: [1, 1]"}
    defaults[field.split(":")[0]] = field
    box = ", ".join(defaults.values())
    err = check(MATS + f"parts:\n  p:\n    material: steel\n    box: {{{box}}}\n")
    assert err.line == 6 and err.path == f"parts.p.box.{field.split(':')[0]}"
    assert err.message == message


def test_union_branches_are_merged_into_one_expectation() -> None:
    err = check(MATS + "parts:\n  p: {material: steel, scale: big}\n")
    assert where(err) == (4, 31, "parts.p.scale")
    assert err.message == "expected a number or a list, got 'big' (str)"
    assert len(err.errors) == 1


def test_list_items_are_located() -> None:
    err = check(MATS + "items:\n  - material: steel\n  - material: steel\n    count: 1.5\n")
    assert where(err) == (6, 12, "items[1].count")
    assert err.message == "expected an integer, got 1.5 (float)"


def test_literal_dict_keys() -> None:
    err = check(MATS + "axes: {x: 1.0, z: 2.0}\n")
    assert where(err) == (3, 16, "axes.z")
    assert err.message == "unknown key 'z' (expected one of: x, y)"


def test_cross_reference_with_path_marker() -> None:
    err = check(MATS + "parts:\n  plate:\n    material: stel\n")
    assert where(err) == (5, 5, "parts.plate.material")
    assert err.message == "unknown material 'stel' (known: steel)"
    assert str(err) == "t.yaml:5:5: parts.plate.material: unknown material 'stel' (known: steel)"


def test_path_marker_with_dotted_list_index() -> None:
    err = check(MATS + "items:\n  - material: steel\n  - {count: 2, material: water}\n")
    assert where(err) == (5, 16, "items[1].material")


def test_path_marker_is_relative_to_the_raising_model() -> None:
    err = check(MATS + "parts:\n  p:\n    material: steel\n    count: 13\n")
    assert where(err) == (6, 5, "parts.p.count") and err.message == "unlucky number"


def test_empty_path_marker_means_the_model_itself() -> None:
    err = check(MATS + "parts:\n  p:\n    material: steel\n    count: 15\n")
    assert where(err) == (4, 3, "parts.p") and err.message == "the whole part is wrong"


def test_path_marker_falls_back_to_an_absolute_path() -> None:
    err = check("top: y\n" + MATS + "parts:\n  p: {material: steel, count: 16}\n")
    assert where(err) == (1, 1, "top") and err.message == "absolute path"


def test_validator_message_without_marker() -> None:
    err = check(MATS + "parts:\n  p: {material: steel, count: 14}\n")
    assert where(err) == (4, 3, "parts.p") and err.message == "count 14 is not allowed"


def test_errors_are_sorted_by_position() -> None:
    err = check("materials:\n  a: {type: elastic, density: -1.0}\n"
                "  b: {type: fluid, density: 1.0}\nitems: [{material: 1}]\n")
    lines = [e.line for e in err.errors]
    assert lines == sorted(lines) and len(err.errors) == 3


def _header(path: Path) -> re.Match[str]:
    match = HEADER.match(path.read_bytes().split(b"\n", 1)[0].decode())
    assert match, f"{path.name}: first line must be '# expect-line: N ...'"
    return match


def test_there_are_enough_bad_decks() -> None:
    assert len(BAD_DECKS) >= 20


@pytest.mark.parametrize("deck", BAD_DECKS, ids=lambda p: p.stem)
def test_bad_deck_raises_one_located_deck_error(deck: Path) -> None:
    expect = _header(deck)
    with pytest.raises(DeckError) as info:
        load_deck(deck)
    text = str(info.value)
    match = ONE_LINE.match(text)
    assert match and "\n" not in text, text
    assert match["file"] == str(deck)
    assert int(match["line"]) == int(expect[1]), text
    if expect[2]:
        assert match["path"] == expect[2], text
    if expect[3]:
        assert expect[3] in match["msg"], text


def _assert_cli_failure(deck: Path, exit_code: int, stderr: str, stdout: str) -> None:
    assert exit_code == 65, stderr
    assert "Traceback" not in stderr + stdout
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    match = re.match(rf"^{re.escape(str(deck))}:(\d+):\d+: \S+: .+", lines[0])
    assert match, lines[0]
    assert int(match[1]) == int(_header(deck)[1]), lines[0]


@pytest.fixture(scope="module")
def cli_main():
    if importlib.util.find_spec("sphfem_cli.cli") is None:
        pytest.skip("sphfem_cli/cli.py does not exist yet")
    from sphfem_cli.cli import main

    return main


@pytest.mark.parametrize("deck", BAD_DECKS, ids=lambda p: p.stem)
def test_cli_check_exits_65_with_one_line(deck: Path, cli_main) -> None:
    from click.testing import CliRunner

    result = CliRunner().invoke(cli_main, ["check", str(deck)])
    assert isinstance(result.exception, SystemExit | None), result.exception
    _assert_cli_failure(deck, result.exit_code, result.stderr, result.stdout)


SUBPROCESS_SAMPLE = ["syntax_tab_indent", "empty", "unknown_key_material", "unknown_material",
                     "not_utf8"]


@pytest.mark.parametrize("name", SUBPROCESS_SAMPLE)
def test_installed_sphfem_check_exits_65(name: str, cli_main) -> None:
    exe = Path(sys.executable).with_name("sphfem")
    if not exe.exists():
        pytest.skip("the sphfem console script is not installed beside this Python")
    deck = next(d for d in BAD_DECKS if d.stem == name)
    result = subprocess.run([str(exe), "check", str(deck)], capture_output=True, text=True,
                            timeout=120)
    _assert_cli_failure(deck, result.returncode, result.stderr, result.stdout)


# ------------------------------------------------------------------ bounded parsing (issue 13, item 1)

SMALL_DECK = (Path(__file__).parents[1] / "data" / "fuzz" / "fsi_sph.yaml").read_text(encoding="utf-8")


def _check_cli(deck: Path, cli_main):
    from click.testing import CliRunner

    result = CliRunner().invoke(cli_main, ["check", str(deck)])
    assert isinstance(result.exception, SystemExit | None), result.exception
    assert "Traceback" not in result.output
    return result


def _one_deck_error(deck: Path, cli_main) -> re.Match[str]:
    result = _check_cli(deck, cli_main)
    lines = result.output.strip().splitlines()
    assert result.exit_code == 65 and len(lines) == 1, result.output
    match = ONE_LINE.match(lines[0])
    assert match and match["file"] == str(deck), lines[0]
    return match


@pytest.mark.parametrize("levels", [5, 9])
def test_alias_bomb_stops_at_the_value_bound(tmp_path, levels, cli_main) -> None:
    bomb = "b0: &b0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]\n" + "".join(
        f"b{k}: &b{k} [{', '.join([f'*b{k - 1}'] * 10)}]\n" for k in range(1, levels + 1))
    deck = tmp_path / "bomb.yaml"
    deck.write_text(SMALL_DECK + bomb)
    match = _one_deck_error(deck, cli_main)
    assert "more values than 100000" in match["msg"] and "SPHFEM_MAX_DECK_NODES" in match["msg"]


def test_merge_key_bomb_stops_at_the_value_bound(tmp_path, cli_main) -> None:
    bomb = "m0: &m0 {a: 1, b: 2}\n" + "".join(
        f"m{k}: &m{k} {{<<: [{', '.join([f'*m{k - 1}'] * 10)}]}}\n" for k in range(1, 8))
    deck = tmp_path / "merge.yaml"
    deck.write_text(SMALL_DECK + bomb)
    assert "SPHFEM_MAX_DECK_NODES" in _one_deck_error(deck, cli_main)["msg"]


@pytest.mark.parametrize("depth", [1000, 20000])
@pytest.mark.parametrize("style", ["flow_list", "flow_map", "block"])
def test_deep_nesting_stops_at_the_depth_bound(tmp_path, depth, style, cli_main) -> None:
    if style == "flow_list":
        value = "[" * depth + "1" + "]" * depth
    elif style == "flow_map":
        value = "{a: " * depth + "1" + "}" * depth
    else:
        value = "\n" + "".join(" " * (i + 1) + "a:\n" for i in range(depth // 10)) + " " * (depth // 10 + 1) + "1"
    deck = tmp_path / "deep.yaml"
    deck.write_text(SMALL_DECK + f"deep: {value}\n")
    match = _one_deck_error(deck, cli_main)
    assert int(match["line"]) >= SMALL_DECK.count("\n") + 1
    assert "nested deeper than 100" in match["msg"] and "SPHFEM_MAX_DECK_DEPTH" in match["msg"]


def test_depth_bound_raised_past_the_stack_is_still_one_line(tmp_path, monkeypatch, cli_main) -> None:
    monkeypatch.setenv("SPHFEM_MAX_DECK_DEPTH", "1000000")
    deck = tmp_path / "deep.yaml"
    deck.write_text(SMALL_DECK + "deep: " + "[" * 20000 + "1" + "]" * 20000 + "\n")
    assert "Python's stack" in _one_deck_error(deck, cli_main)["msg"]


def test_size_bound_refuses_a_huge_file_at_once(tmp_path, cli_main) -> None:
    deck = tmp_path / "huge.yaml"
    with deck.open("w") as fh:
        fh.write(SMALL_DECK)
        fh.write(("# " + "x" * 78 + "\n") * 375_000)  # 30 MB of comments
    match = _one_deck_error(deck, cli_main)
    assert (match["line"], match["col"]) == ("1", "1")
    assert "larger than 8388608 bytes" in match["msg"] and "SPHFEM_MAX_DECK_BYTES" in match["msg"]


def test_bounds_can_be_raised_and_a_bad_bound_is_one_line(tmp_path, monkeypatch, cli_main) -> None:
    deck = tmp_path / "deck.yaml"
    deck.write_text(SMALL_DECK)
    monkeypatch.setenv("SPHFEM_MAX_DECK_BYTES", "100")
    assert "SPHFEM_MAX_DECK_BYTES" in _one_deck_error(deck, cli_main)["msg"]
    monkeypatch.setenv("SPHFEM_MAX_DECK_BYTES", str(10**6))
    assert _check_cli(deck, cli_main).exit_code == 0
    monkeypatch.setenv("SPHFEM_MAX_DECK_NODES", "ten")
    assert "SPHFEM_MAX_DECK_NODES='ten' must be a positive integer" in _one_deck_error(deck, cli_main)["msg"]


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_a_deck_must_be_a_regular_file(tmp_path, kind, cli_main) -> None:
    import os

    deck = {"fifo": tmp_path / "deck.yaml", "device": Path("/dev/zero")}[kind]
    if kind == "fifo":
        os.mkfifo(deck)
    assert "not a regular file" in _one_deck_error(deck, cli_main)["msg"]


def test_a_directory_is_not_a_deck(tmp_path) -> None:  # the CLI refuses it as a usage error first
    from sphfem_cli.deck.loader import load

    with pytest.raises(DeckError, match="is a directory, not a regular file"):
        load(tmp_path)


def _solid_deck_with_mesh(tmp_path: Path, mesh: Path) -> Path:
    deck = tmp_path / "mesh_deck.yaml"
    deck.write_text(f"""dimension: 3
control: {{end_time: 1.0e-4}}
materials:
  steel: {{type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}}
sections:
  solid: {{type: solid}}
parts:
  block:
    material: steel
    section: solid
    geometry:
      file: {{file: {mesh}}}
""")
    return deck


@pytest.mark.parametrize("kind", ["fifo", "directory", "truncated_vtu", "garbage_msh", "bad_inp", "empty_msh"])
def test_unreadable_mesh_file_is_an_error_at_its_file_key(tmp_path, kind, cli_main) -> None:
    import os

    good = (Path(__file__).parents[1] / "data" / "hex_2x1x1_flipped.vtu").read_bytes()
    mesh = tmp_path / {"fifo": "m.vtu", "directory": "d.vtu", "truncated_vtu": "t.vtu", "garbage_msh": "g.msh",
                       "bad_inp": "b.inp", "empty_msh": "e.msh"}[kind]
    if kind == "fifo":
        os.mkfifo(mesh)
    elif kind == "directory":
        mesh.mkdir()
    else:
        mesh.write_bytes({"truncated_vtu": good[: len(good) // 2], "garbage_msh": bytes(range(256)) * 8,
                          "bad_inp": b"*NODE\n1, a, b, c\n*ELEMENT, TYPE=C3D8\n1, 1\n", "empty_msh": b""}[kind])
    match = _one_deck_error(_solid_deck_with_mesh(tmp_path, mesh), cli_main)
    assert (match["line"], match["path"]) == ("12", "parts.block.geometry.file.file"), match[0]
    assert str(mesh) in match["msg"]


def test_re_entrant_imported_element_names_the_element_and_part(tmp_path, cli_main) -> None:
    import meshio
    import numpy as np

    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1],
                       [2, 0, 0], [2, 1, 0], [2, 0, 1], [2, 1, 1]], dtype=float)
    points[6] = [0.2, 0.2, 0.2]  # element 1's shared corner pushed deep inside element 0: a re-entrant hex
    cells = [("hexahedron", np.array([[0, 1, 2, 3, 4, 5, 6, 7], [1, 8, 9, 2, 5, 10, 11, 6]]))]
    mesh = tmp_path / "reentrant.vtu"
    meshio.write(mesh, meshio.Mesh(points, cells))
    match = _one_deck_error(_solid_deck_with_mesh(tmp_path, mesh), cli_main)
    assert match["path"] == "parts.block.geometry.file.file"
    assert re.search(r"element \d of part 'block' is inverted, collapsed or re-entrant at t = 0", match["msg"])


@pytest.mark.parametrize("deck_name", ["cantilever_2d", "cantilever_3d"])
def test_overflowing_box_is_a_deck_error_at_its_geometry(tmp_path, deck_name, cli_main) -> None:
    """A box reaching 1e308 (finite coordinates, an element volume that overflows) is refused at the box's line,
    not an internal error in the first element pass (a fuzz-found case)."""
    text = (Path(__file__).parents[2] / "decks" / f"{deck_name}.yaml").read_text(encoding="utf-8")
    deck = tmp_path / "huge.yaml"
    deck.write_text(text.replace("max: [1.0, 0.025", "max: [1.0, 1.0e308"))
    match = _one_deck_error(deck, cli_main)
    assert match["path"] == "parts.beam.geometry.box" and "beyond 1e+100" in match["msg"], match[0]


# ------------------------------------------------------------------ check checks what run needs (item 2)

def test_unicode_names_check_and_run(tmp_path, cli_main) -> None:
    from click.testing import CliRunner

    text = (SMALL_DECK.replace("column", "名前").replace("rubber", "🔥").replace("block", "Ünï blöck")
            .replace("end_time: 0.02", "end_time: 0.0005")
            .replace("output: {interval: 0.005, history_interval: 0.0005}",
                     "output:\n  interval: 0.0005\n  history_interval: 0.0001\n"
                     "  histories: [{name: ënergie, part: Ünï blöck, quantities: [displacement]}]"))
    deck = tmp_path / "名前.yaml"
    deck.write_text(text, encoding="utf-8")
    assert _check_cli(deck, cli_main).exit_code == 0
    out = tmp_path / "out"
    result = CliRunner().invoke(cli_main, ["run", "-q", str(deck), "-o", str(out)])
    assert result.exit_code == 0, result.output
    header = (out / "histories" / "matsum.csv").read_text(encoding="utf-8").splitlines()[0]
    assert "名前_kinetic" in header and "Ünï blöck_internal" in header
    assert (out / "histories" / "ënergie.csv").read_text(encoding="utf-8").startswith("time,displacement_x")


@pytest.mark.parametrize("name, why", [("a,b", "','"), ("x/y", "'/'"), ("", "empty"), ("  ", "blank"),
                                       ("..", "cannot be a name"), ("tab\\there", "U+0009"),
                                       ("line\\u2028sep", "U+2028"), ("n" * 101, "at most 100")])
def test_names_no_output_file_can_carry_are_refused(name, why) -> None:
    from sphfem_cli.deck.loader import loads
    from sphfem_cli.deck.schema import Deck

    text = SMALL_DECK.replace("  rubber:", f'  "{name}":').replace("material: rubber", f'material: "{name}"')
    data, positions = loads(text, "deck.yaml")
    with pytest.raises(DeckError) as info:
        validate_model(Deck, data, positions, "deck.yaml")
    assert why in info.value.message and info.value.line == 9, str(info.value)


def test_a_chain_of_aliases_nests_no_deeper_than_the_bound() -> None:
    from sphfem_cli.deck.loader import loads

    chain = "a0: &a0 [1]\n" + "".join(f"a{k}: &a{k} [*a{k - 1}]\n" for k in range(1, 1500))
    with pytest.raises(DeckError, match=r"with its aliases expanded, lists and mappings nest deeper than 100 "
                                        r".*SPHFEM_MAX_DECK_DEPTH"):
        loads(chain, "deck.yaml")


def test_dummy_walls_too_large_for_memory_are_refused_before_allocation(tmp_path, cli_main) -> None:
    deck = tmp_path / "walls.yaml"
    deck.write_text(SMALL_DECK.replace(
        "  - {type: fixed, set: block_base}",
        "  - {type: fixed, set: block_base}\n"
        "  - {type: dummy_wall, region: {box: {min: [0.0, -1.0], max: [1000.0, 0.0]}}, spacing: 1.0e-5}"))
    match = _one_deck_error(deck, cli_main)
    assert match["path"] == "boundaries[2]" and "the dummy wall particles need about" in match["msg"], match[0]


DAM_BREAK = (Path(__file__).parents[2] / "decks" / "dam_break_2d.yaml").read_text(encoding="utf-8")


@pytest.mark.parametrize("old, new, path, text", [
    ("reference_density: 1000.0", "reference_density: 1.0e30", "parts.column.hydrostatic",
     "times the material's density (allowed: 1/2 to 2)"),
    ("density: 1000.0, viscosity", "density: 1.0e-300, viscosity", "parts.column.material",
     "an initial density of 1e-300 is outside [1.49e-154, 1.34e+154]"),
])
def test_sph_state_that_would_break_the_first_step_is_a_deck_error(tmp_path, old, new, path, text, cli_main) -> None:
    deck = tmp_path / "dam.yaml"
    assert old in DAM_BREAK
    deck.write_text(DAM_BREAK.replace(old, new, 1))
    match = _one_deck_error(deck, cli_main)
    assert match["path"] == path and text in match["msg"], match[0]


def test_corner_jacobians_see_what_the_centre_value_misses() -> None:
    import numpy as np

    from sphfem_cli.model import mesh as meshgen

    box = meshgen.box_mesh([0.0, 0.0, 0.0], [1.0, 2.0, 3.0], divisions=[1, 1, 1])
    assert np.allclose(meshgen.corner_jacobians(box.nodes, box.elements), 6.0)  # edge lengths 1 x 2 x 3
    arrow = np.array([[0.0, 0.0], [2.0, 0.0], [0.3, 0.3], [0.0, 2.0]])  # a re-entrant quad, positive area
    quad = np.array([[0, 1, 2, 3]])
    assert meshgen.element_jacobian_sign_check(arrow, quad)[0] > 0
    assert np.allclose(meshgen.corner_jacobians(arrow, quad), [[4.0, 0.6, -2.8, 0.6]])


@pytest.mark.parametrize("old, new, path, text", [
    ("youngs_modulus: 1.0e6", "youngs_modulus: 1.0e300", "materials.rubber", "the Young's modulus 1e+300 is over 1.34e+154"),
    ("smoothing_ratio: 1.2}", "smoothing_ratio: 1.2, density_diffusion: 1.0e29}", "sections.fluid.density_diffusion",
     "must be <= 1"),
    ("acceleration: [0.0, -9.81]", "acceleration: [0.0, -1.0e-300]", None, None),  # tiny but valid: no warning
])
def test_constants_the_kernels_cannot_square_are_deck_errors(tmp_path, old, new, path, text, cli_main) -> None:
    deck = tmp_path / "fsi.yaml"
    assert old in SMALL_DECK
    deck.write_text(SMALL_DECK.replace(old, new, 1))
    if path is None:
        result = _check_cli(deck, cli_main)
        assert result.exit_code == 0 and "Warning" not in result.output, result.output
        return
    match = _one_deck_error(deck, cli_main)
    assert match["path"] == path and text in match["msg"], match[0]


def test_lines_are_counted_at_newlines_only() -> None:
    """PyYAML also breaks lines at NEL (U+0085) and U+2028 / U+2029; editors do not, so positions are counted
    at "\\n" only. Found by the deck fuzzer: a key renamed to NEL inside an unclosed quote was reported on line 5
    of a 4-line file."""
    text = 'a: 1\nb: "x\x85y\n'
    with pytest.raises(DeckError) as info:
        loads(text, "t.yaml")
    assert (info.value.line, info.value.col) == (text.count("\n") + 1, 1), str(info.value)  # the end of the text
    _, positions = loads('a: "x\x85y"\nmaterials:\n  steel: {type: elastic}\n', "t.yaml")  # values after a NEL
    assert positions.position_of(("materials", "steel")) == (3, 3)
    _, positions = loads('a: "x\u2028y"\nz: [1, 2]\n', "t.yaml")
    assert positions.position_of(("z",)) == (2, 1)
