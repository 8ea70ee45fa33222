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
