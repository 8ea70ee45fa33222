"""YAML loading with positions: YAML 1.2 scalars, duplicate keys, positions, syntax errors."""
from __future__ import annotations

import math
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sphfem_cli.deck.errors import DeckError, DeckErrors, did_you_mean, format_path, parse_path
from sphfem_cli.deck.loader import Positions, load, loads, resolve_plain_scalar

ONE_LINE = re.compile(r"^[^\n]+:\d+:\d+: \S+: [^\n]+$")


def error_of(text: str) -> DeckError:
    with pytest.raises(DeckError) as info:
        loads(text, "deck.yaml")
    assert ONE_LINE.match(str(info.value)), str(info.value)
    return info.value


@pytest.mark.parametrize(
    "text, value",
    [
        ("1e-3", 1e-3), ("1.0e+5", 1.0e5), (".5", 0.5), ("-2E3", -2000.0), ("+1.5", 1.5),
        ("1.", 1.0), ("0.0", 0.0), ("12", 12), ("-3", -3), ("+7", 7), ("007", 7),
        ("0x1F", 31), ("0o17", 15), ("true", True), ("True", True), ("TRUE", True),
        ("false", False), ("FALSE", False), ("null", None), ("Null", None), ("~", None),
        ("", None), ("yes", "yes"), ("no", "no"), ("on", "on"), ("off", "off"),
        ("1_000", "1_000"), ("0b101", "0b101"), ("1:30", "1:30"), ("-0x1F", "-0x1F"),
        ("tRUE", "tRUE"), ("1e", "1e"), (".", "."), ("steel", "steel"), ("-.nan", "-.nan"),
    ],
)
def test_plain_scalars_follow_yaml_1_2_core_schema(text: str, value: object) -> None:
    got = resolve_plain_scalar(text)
    assert got == value and type(got) is type(value)
    data, _ = loads(f"a: {text}\n")
    assert data["a"] == value and type(data["a"]) is type(value)


@pytest.mark.parametrize("text, sign", [(".inf", 1), ("-.inf", -1), ("+.INF", 1), (".Inf", 1)])
def test_infinities(text: str, sign: int) -> None:
    assert resolve_plain_scalar(text) == sign * math.inf


@pytest.mark.parametrize("text", [".nan", ".NaN", ".NAN"])
def test_nan(text: str) -> None:
    assert math.isnan(resolve_plain_scalar(text))


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_python_float_reprs_read_back_as_the_same_float(x: float) -> None:
    assert resolve_plain_scalar(repr(x)) == x


@given(st.integers())
def test_integers_read_back(n: int) -> None:
    assert resolve_plain_scalar(str(n)) == n


def test_quoted_and_block_scalars_are_strings() -> None:
    data, _ = loads("a: '12'\nb: \"1e-3\"\nc: 'true'\nd: |\n  12\ne: >\n  null\nf: ''\n")
    assert data == {"a": "12", "b": "1e-3", "c": "true", "d": "12\n", "e": "null\n", "f": ""}


def test_explicit_tags() -> None:
    data, _ = loads("a: !!str 12\nb: !!float 3\nc: !!int '7'\nd: !!bool true\ne: !!null ~\n")
    assert data == {"a": "12", "b": 3.0, "c": 7, "d": True, "e": None}
    assert type(data["b"]) is float


@pytest.mark.parametrize("text, message", [("a: !!int x\n", "'x' is not a valid int"),
                                           ("a: !custom 1\n", "unsupported tag '!custom'"),
                                           ("a: !!set {x: 1}\n", "unsupported tag")])
def test_bad_tags(text: str, message: str) -> None:
    err = error_of(text)
    assert message in err.message and (err.line, err.col, err.path) == (1, 4, "a")


def test_nested_structures() -> None:
    data, _ = loads("a:\n  b: [1, {c: 2}]\n  d: {e: [x, y]}\n")
    assert data == {"a": {"b": [1, {"c": 2}], "d": {"e": ["x", "y"]}}}


def test_duplicate_key_points_at_the_second() -> None:
    err = error_of("a: 1\nb:\n  c: 1\n  d: 2\n  c: 3\n")
    assert (err.line, err.col, err.path) == (5, 3, "b.c")
    assert err.message == "duplicate key 'c' (first at line 3)"


def test_duplicate_key_in_flow_mapping_and_list_item() -> None:
    err = error_of("a: {x: 1, x: 2}\n")
    assert (err.line, err.col, err.path) == (1, 11, "a.x")
    err = error_of("l:\n  - p: 1\n    q: 2\n    p: 3\n")
    assert (err.line, err.col, err.path) == (4, 5, "l[0].p")


@pytest.mark.parametrize("text", ["1: a\n", "true: a\n", "~: a\n", "1.5: a\n"])
def test_non_string_keys_are_rejected(text: str) -> None:
    err = error_of(text)
    assert "is not a name" in err.message and (err.line, err.col) == (1, 1)


def test_complex_keys_are_rejected() -> None:
    err = error_of("? [1, 2]\n: a\n")
    assert "mapping keys must be plain names" in err.message


def test_quoted_numeric_keys_are_names() -> None:
    assert loads("'1': a\n")[0] == {"1": "a"}


DECK = """\
title: t
parts:
  plate:
    material: steel
    nodes: [1, 2,
            3]
  block: {material: water, section: s}
boundaries:
  - type: fixed
    dirs: [x]
  - {type: free}
"""


def test_positions_of_keys_items_and_values() -> None:
    _, pos = loads(DECK)
    assert isinstance(pos, Positions)
    assert pos[()] == (1, 1)
    assert pos[("title",)] == (1, 1) and pos.values[("title",)] == (1, 8)
    assert pos[("parts", "plate", "material")] == (4, 5)
    assert pos.values[("parts", "plate", "material")] == (4, 15)
    assert pos[("parts", "plate", "nodes", 2)] == (6, 13)
    assert pos[("parts", "block", "section")] == (7, 28)
    assert pos.values[("parts", "block")] == (7, 10)
    assert pos[("boundaries", 0)] == (9, 5)
    assert pos[("boundaries", 0, "dirs")] == (10, 5)
    assert pos[("boundaries", 0, "dirs", 0)] == (10, 12)
    assert pos[("boundaries", 1)] == (11, 5)
    assert pos[("boundaries", 1, "type")] == (11, 6)


def test_position_of_walks_up_to_the_nearest_known_ancestor() -> None:
    _, pos = loads(DECK)
    assert pos.position_of(("parts", "plate", "section")) == (3, 3)
    assert pos.position_of(("parts", "plate", "material", "x", "y")) == (4, 5)
    assert pos.position_of(("nothing", 3)) == (1, 1)
    assert pos.position_of(("parts", "plate", "material"), value=True) == (4, 15)
    assert pos.position_of(("parts", "plate", "missing"), value=True) == (3, 3)
    assert pos.position_of(("boundaries", "1", "type")) == (11, 6)
    assert pos.position_of(("parts", "plate", "nodes", "1"), value=True) == (5, 16)


def test_anchors_aliases_and_merge_keys() -> None:
    text = ("base: &b {density: 1.0, e: 2.0}\n"
            "more: &m {e: 5.0, nu: 0.3}\n"
            "steel:\n  <<: *b\n  e: 3.0\n"
            "mix:\n  <<: [*m, *b]\n"
            "copy: *b\n")
    data, pos = loads(text)
    assert data["steel"] == {"e": 3.0, "density": 1.0}
    assert data["mix"] == {"e": 5.0, "nu": 0.3, "density": 1.0}
    assert data["copy"] == {"density": 1.0, "e": 2.0}
    assert pos[("steel", "e")] == (5, 3)
    assert pos[("steel", "density")] == (1, 11)
    assert pos[("copy",)] == (8, 1)


def test_a_quoted_merge_key_is_an_ordinary_key() -> None:
    assert loads("'<<': 1\n")[0] == {"<<": 1}


@pytest.mark.parametrize("text, message", [
    ("a: &x [1, *x]\n", "recursive alias"),
    ("a: &x {b: 1, <<: *x}\n", "recursive merge"),
    ("a: {<<: 3}\n", "merge key"),
])
def test_bad_aliases_and_merges(text: str, message: str) -> None:
    assert message in error_of(text).message


@pytest.mark.parametrize("text, line, col, fragment", [
    ("a: b: c\n", 1, 5, "mapping values are not allowed here"),
    ("a:\n  b: 1\n c: 2\n", 3, 2, "expected <block end>"),
    ("a: [1, 2\n", 2, 1, "expected ',' or ']'"),
    ("a:\n\tb: 1\n", 2, 1, "found character '\\t'"),
    ("a: 'open\n", 2, 1, "unexpected end of stream"),
    ("a: *nope\n", 1, 4, "found undefined alias 'nope'"),
    ("a: \x07\n", 1, 4, "unacceptable character #x0007"),
    ("a: 1\n---\nb: 2\n", 2, 1, "more than one YAML document"),
])
def test_syntax_errors_are_one_line_with_position(text: str, line: int, col: int,
                                                  fragment: str) -> None:
    err = error_of(text)
    assert (err.line, err.col, err.path) == (line, col, "yaml")
    assert fragment in err.message
    assert str(err).startswith(f"deck.yaml:{line}:{col}: yaml: ")


@pytest.mark.parametrize("text", ["", "\n\n", "# only a comment\n"])
def test_empty_stream(text: str) -> None:
    err = error_of(text)
    assert (err.line, err.col) == (1, 1) and "empty" in err.message


def test_an_explicit_null_document_is_not_empty() -> None:
    assert loads("--- ~\n")[0] is None


def test_load_reads_files(tmp_path) -> None:
    path = tmp_path / "d.yaml"
    path.write_text("\ufeffa: 1\n", encoding="utf-8")
    data, pos = load(path)
    assert data == {"a": 1} and pos[("a",)] == (1, 1)


def test_load_file_problems(tmp_path) -> None:
    for path, message in [(tmp_path / "none.yaml", "no such file"), (tmp_path, "is a directory")]:
        with pytest.raises(DeckError) as info:
            load(path)
        assert (info.value.line, info.value.col, info.value.file) == (1, 1, str(path))
        assert message in info.value.message
    bad = tmp_path / "latin1.yaml"
    bad.write_bytes(b"a: 1\nb: caf\xe9\n")
    with pytest.raises(DeckError) as info:
        load(bad)
    assert (info.value.line, info.value.col) == (2, 7) and "not UTF-8" in info.value.message


def test_deck_error_is_one_line() -> None:
    err = DeckError("unknown material 'stel'\n (known: steel,\twater)", file="deck.yaml", line=12,
                    col=5, path="parts.plate.material")
    assert str(err) == ("deck.yaml:12:5: parts.plate.material: unknown material 'stel' "
                        "(known: steel, water)")
    assert str(DeckError("empty", file="d.yaml")) == "d.yaml:1:1: <root>: empty"


def test_deck_errors_prints_as_its_first() -> None:
    first = DeckError("a", file="f", line=2, col=3, path="x")
    agg = DeckErrors([first, DeckError("b", file="f", line=9, col=1, path="y")])
    assert isinstance(agg, DeckError) and str(agg) == str(first) and len(agg.errors) == 2
    with pytest.raises(ValueError):
        DeckErrors([])


def test_did_you_mean() -> None:
    assert did_you_mean("stel", ["steel", "water"]) == "steel"
    assert did_you_mean("Densty", ["density", "viscosity"]) == "density"
    assert did_you_mean("zzz", ["steel", "water"]) is None
    assert did_you_mean(3, ["steel"]) is None
    assert did_you_mean("x", []) is None


@pytest.mark.parametrize("path, text", [
    ((), ""), (("parts", "plate", "material"), "parts.plate.material"),
    (("boundaries", 0, "part"), "boundaries[0].part"), (("a", 1, 2), "a[1][2]"),
])
def test_paths_round_trip(path: tuple, text: str) -> None:
    assert format_path(path) == text
    assert parse_path(text) == path


def test_parse_path_keeps_dotted_indices_as_strings() -> None:
    assert parse_path("boundaries.0.part") == ("boundaries", "0", "part")
    assert parse_path("<root>") == ()
