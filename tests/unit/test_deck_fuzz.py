"""Deck fuzzing: mutated decks either check (or run) cleanly or fail with one deck error; never a traceback.

The bases are every shipped deck (decks/*.yaml) plus two small fluid-structure decks with `contacts`
and `couplings` (tests/data/fuzz), each parsed once. A hypothesis-drawn mutant applies one or two
mutations to the tree and writes it back as YAML (`emit` below):

- tree: delete a key or list entry; replace a value by another type, an extreme or non-finite
  number (1e308, -0, nan, inf, 1e-300, 5e-324), a huge count, a name nothing defines; rename an
  entity (part, material, set...) everywhere, to Unicode or to a name no file can carry; lengthen
  or shorten a numeric vector; put arbitrary Unicode text in a string;
- YAML: a tag on a value (``!!python/object/apply``, ``!!binary``, ``!custom``...), an anchor and
  an alias or a merge key ``<<`` between two values, an alias bomb, nesting 50 to 20 000 deep;
- bytes: random bytes spliced into the file, the file truncated, the file padded past the size bound.

`check` (click's CliRunner, in process) sees FUZZ_CHECK_CASES mutants (FUZZ_CHECK_CASES_LONG more under
`-m validation`); bases with more than about 3000
elements and particles (``_size``, from the deck's geometry counts) are drawn a quarter as often as the others (the largest ALE decks take 0.2 to
3 s a check, the small decks about 20 ms). Each must exit 0, or 65 with exactly one line ``file:line:col: path: message`` whose line
lies in the file, within MUTANT_SECONDS of CPU time. The deck bounds are lowered for the fuzzing
(SPHFEM_MAX_DECK_NODES, SPHFEM_MAX_DECK_BYTES: module fixture) so that bombs and huge files stop
after milliseconds; the default bounds have their own tests in test_deck_errors.py.
`run` sees mutants of the small decks, capped at RUN_STEP_CAP steps: exit 0 (every output finite),
3 (a guard stop: one line and a diagnosis) or 65.
"""
from __future__ import annotations

import json
import math
import re
import signal
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sphfem_cli.cli import main
from sphfem_cli.deck import loader

FUZZ_DIR = Path(__file__).parents[1] / "data" / "fuzz"
SHIPPED = sorted((Path(__file__).parents[2] / "decks").glob("*.yaml"))
DECKS = SHIPPED + sorted(FUZZ_DIR.glob("*.yaml"))
RUN_DECKS = sorted(FUZZ_DIR.glob("*.yaml"))
RUN_STEP_CAP = 60
FUZZ_CHECK_CASES = 200  # default suite: about 10 s of CPU (500 took 24 s at idle, December 2026)
FUZZ_CHECK_CASES_LONG = 3000  # -m validation
MUTANT_SECONDS = 20.0  # CPU seconds per mutant (the process's, so the machine's load does not count); a spin never ends
MUTANT_WALL_SECONDS = 300.0  # and wall seconds, for a hang that waits without computing
FUZZ_LIMITS = {"SPHFEM_MAX_DECK_NODES": "5000", "SPHFEM_MAX_DECK_BYTES": "262144"}
ONE_LINE = r":(\d+):(\d+): .+"  # then "path: message"; a path may hold any name, spaces included

NUMBERS = [-1, 0, 1, 3, 2.5, -2.5e3, 1e308, -1e308, math.nan, math.inf, -math.inf, 10**12, 10**9, 5e-324,
           1e-300, -1e-300, -0.0, 0.0, 2e-308, 1e30, -1e30, 10**30]
REPLACEMENTS = NUMBERS + [
    None, "text", "steel", "", True, False, [], {}, [1.0], [1.0, 2.0, 3.0, 4.0], {"type": "elastic"},
    {"unknown": 1}, "no_such_name", [10**6, 10**6], [10**9, 1], [math.nan, 0.0], [math.inf, 1.0],
    [[1.0, 2.0]], {"box": {"min": [0, 0], "max": [0, 0]}},
    {"type": "nodes_to_surface", "nodes": "no_such_name", "surface": "block"},
    {"type": "lagrange_in_solid", "structure": "tank", "fluid": "plate"},
]
NAMES = ["名前", "🔥", "Ünïcödé part", "ɸ_1", "a" * 150, "x,y", "a/b", "..", "", " ", "tab\there",
         "glstat", "new\nline", "quote\"d", "zero\u200bwidth", "\u202eRTL"]
TAGS = ["!!python/object/apply:os.system", "!!python/name:os.system", "!!binary", "!custom", "!!timestamp",
        "!!set", "!!omap", "!!float", "!!int", "!!str", "!!bool", "!!null", "!!seq", "!!map", "!<tag:x,1:y>"]
NAMED = ("curves", "equations_of_state", "materials", "sections", "parts", "sets")


class Tagged:
    """A value written with an explicit YAML tag: ``!!binary x``."""

    def __init__(self, tag: str, value) -> None:
        self.tag, self.value = tag, value


class Anchored:
    """A value written with an anchor: ``&name value``."""

    def __init__(self, name: str, value) -> None:
        self.name, self.value = name, value


class Alias:
    """An alias to an anchor written earlier: ``*name``."""

    def __init__(self, name: str) -> None:
        self.name = name


class Deep:
    """Lists (or single-key mappings) nested `depth` deep around a 1."""

    def __init__(self, depth: int, mappings: bool) -> None:
        self.depth, self.mappings = depth, mappings


def _scalar(value) -> str:
    if value is None:
        return "null"
    if value is True or value is False:
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    return json.dumps(str(value), ensure_ascii=False)  # a JSON string is a YAML double-quoted scalar


def _flow(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_scalar(k) if k != '<<' else k}: {_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    if isinstance(value, Tagged):
        return f"{value.tag} {_scalar(value.value)}"
    if isinstance(value, Anchored):
        return f"&{value.name} {_flow(value.value)}"
    if isinstance(value, Alias):
        return f"*{value.name}"
    if isinstance(value, Deep):
        return ("{a: " * value.depth + "1" + "}" * value.depth if value.mappings
                else "[" * value.depth + "1" + "]" * value.depth)
    return _scalar(value)


def emit(tree) -> str:
    """YAML for a mutated tree: one block line per top-level key (and per part), flow style below."""
    if not isinstance(tree, dict):
        return _flow(tree) + "\n"
    lines = []
    for key, value in tree.items():
        if isinstance(value, dict) and value and key in ("parts", "materials"):
            lines.append(f"{_scalar(key)}:")
            lines += [f"  {_scalar(k)}: {_flow(v)}" for k, v in value.items()]
        else:
            lines.append(f"{_scalar(key) if key != '<<' else key}: {_flow(value)}")
    return "\n".join(lines) + "\n"


def _parse(deck: Path):
    return loader.loads(deck.read_text(encoding="utf-8"), str(deck))[0]


BASES = {deck: _parse(deck) for deck in DECKS}


def _size(tree) -> float:
    """About how many elements and particles a base's parts make (sampling weights only, so that no model is
    built at import): per part, the product of its geometry's ``divisions`` or ``elements_*`` counts, or the
    extent of its box or polygon over its ``element_size`` or ``spacing``."""
    total = 0.0
    for part in (tree.get("parts") or {}).values():
        geometry = part.get("geometry") if isinstance(part, dict) else None
        for shape in (geometry.values() if isinstance(geometry, dict) else ()):
            if not isinstance(shape, dict):
                continue
            counts = [v for k, v in shape.items() if k == "divisions" or k.startswith("elements_")]
            counts = [n for c in counts for n in (c if isinstance(c, list) else [c])]
            corners = shape.get("vertices") or [shape[k] for k in ("min", "max") if k in shape]
            step = shape.get("element_size") or part.get("spacing")
            if counts:
                total += math.prod(counts)
            elif step and corners:
                total += math.prod(max(c) - min(c) for c in zip(*corners)) / step ** len(corners[0])
    return total


# Bases sampled with weights: an ALE box of thousands of elements costs ten times a small deck's check.
WEIGHTED = [d for d in DECKS for _ in range(1 if _size(BASES[d]) > 3000 else 4)]


def _copy(node):
    if isinstance(node, dict):
        return {k: _copy(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_copy(v) for v in node]
    return node


def _leaves(node, path=()):
    """Every (path, value) below the root, containers included, in emission order."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield path + (key,), value
            yield from _leaves(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield path + (i,), value
            yield from _leaves(value, path + (i,))


def _parent(tree, path):
    for key in path[:-1]:
        tree = tree[key]
    return tree


def _rename(node, old, new):
    """Every string equal to `old` (keys and values, but not a `type`) replaced by `new`."""
    if isinstance(node, dict):
        return {(new if k == old else k): (v if k == "type" else _rename(v, old, new)) for k, v in node.items()}
    if isinstance(node, list):
        return [_rename(v, old, new) for v in node]
    return new if node == old else node


def _mutate_tree(data, tree):
    leaves = list(_leaves(tree))
    kind = data.draw(st.sampled_from(["delete", "replace", "replace", "rename", "vector", "unicode", "tag",
                                      "alias", "merge", "deep", "bomb"]), label="kind")
    if kind == "rename":
        families = [f for f in NAMED if isinstance(tree.get(f), dict) and tree[f]]
        if families:
            family = data.draw(st.sampled_from(families), label="family")
            old = data.draw(st.sampled_from(sorted(tree[family])), label="old name")
            new = data.draw(st.sampled_from(NAMES) | st.text(min_size=0, max_size=12), label="new name")
            return _rename(tree, old, new), f"rename {family}.{old} -> {new!r}"
        kind = "replace"
    if kind == "bomb":
        levels = data.draw(st.integers(5, 9), label="levels")
        chain = {f"bomb_{k}": (Anchored(f"b{k}", ["lol"] * 10) if k == 0 else
                               Anchored(f"b{k}", [Alias(f"b{k - 1}")] * 10)) for k in range(levels + 1)}
        key = data.draw(st.sampled_from(["title", "zz_bomb", "curves"]), label="bomb key")
        return {**chain, **{k: v for k, v in tree.items() if k != key}, key: Alias(f"b{levels}")}, \
            f"alias bomb {levels} levels at {key}"
    path, value = data.draw(st.sampled_from(leaves), label="where")
    parent = _parent(tree, path)
    key = path[-1]
    if kind == "delete":
        del parent[key]
    elif kind == "replace":
        parent[key] = _copy(data.draw(st.sampled_from(REPLACEMENTS), label="value"))  # never share REPLACEMENTS
    elif kind == "vector":
        vectors = [(p, v) for p, v in leaves if isinstance(v, list) and v and all(isinstance(x, (int, float))
                                                                                 for x in v)]
        if not vectors:
            return tree, "no vector"
        path, value = data.draw(st.sampled_from(vectors), label="vector")
        grow = data.draw(st.booleans(), label="grow")
        _parent(tree, path)[path[-1]] = value + [data.draw(st.sampled_from(NUMBERS))] if grow else value[:-1]
    elif kind == "unicode":
        strings = [(p, v) for p, v in leaves if isinstance(v, str)]
        path, value = data.draw(st.sampled_from(strings or [(path, value)]), label="string")
        _parent(tree, path)[path[-1]] = data.draw(st.text(max_size=20), label="text")
    elif kind == "tag":
        parent[key] = Tagged(data.draw(st.sampled_from(TAGS), label="tag"),
                             value if not isinstance(value, (dict, list)) else "x")
    elif kind in ("alias", "merge"):
        i = leaves.index((path, value)) if (path, value) in leaves else 0
        later = leaves[i + 1:] if kind == "alias" else [(p, v) for p, v in leaves[i + 1:] if isinstance(v, dict)]
        if not later or (kind == "merge" and not isinstance(value, dict)):
            return tree, f"no {kind}"
        target, _ = data.draw(st.sampled_from(later), label="alias target")
        if path == target[:len(path)]:
            return tree, f"no {kind}"  # the alias would be inside its anchor
        parent[key] = Anchored("a1", value)
        holder = _parent(tree, target)
        if kind == "alias":
            holder[target[-1]] = Alias("a1")
        else:
            holder[target[-1]] = {"<<": Alias("a1"), **holder[target[-1]]}
    elif kind == "deep":
        parent[key] = Deep(data.draw(st.sampled_from([50, 99, 150, 1000, 20000]), label="depth"),
                           data.draw(st.booleans(), label="mappings"))
    return tree, f"{kind} at {path}"


def _mutant_bytes(data, deck: Path) -> tuple[bytes, str]:
    tree = _copy(BASES[deck])
    what = []
    for _ in range(data.draw(st.integers(1, 2), label="mutations")):
        tree, w = _mutate_tree(data, tree)
        what.append(w)
    raw = emit(tree).encode("utf-8")
    tail = data.draw(st.sampled_from(["none"] * 8 + ["binary", "truncate", "huge"]), label="bytes")
    if tail == "binary":
        at = data.draw(st.integers(0, len(raw)), label="at")
        raw = raw[:at] + data.draw(st.binary(min_size=1, max_size=8), label="junk") + raw[at:]
    elif tail == "truncate":
        raw = raw[:data.draw(st.integers(0, len(raw)), label="cut")]
    elif tail == "huge":
        raw += b"# padding\n" * (int(FUZZ_LIMITS["SPHFEM_MAX_DECK_BYTES"]) // 10 + 1)
    return raw, f"{deck.name}: {'; '.join(what)}; bytes {tail}"


class MutantTimeout(BaseException):
    """A mutant ran past MUTANT_SECONDS (a BaseException: the CLI's last-resort handler must not eat it)."""


@contextmanager
def _budget(seconds: float, what: str):
    """Raise MutantTimeout after `seconds` of this process's CPU time (ITIMER_PROF) or MUTANT_WALL_SECONDS of
    wall time (ITIMER_REAL), whichever comes first: a budget in wall time alone failed on a machine at load 6
    (a 3D deck's check took 20 s of wall for a few of CPU)."""
    def expire(signum, frame):
        kind = "CPU" if signum == signal.SIGPROF else "wall"
        raise MutantTimeout(f"{what}: more than {seconds if kind == 'CPU' else MUTANT_WALL_SECONDS:g} s of {kind} time")

    previous = {sig: signal.signal(sig, expire) for sig in (signal.SIGPROF, signal.SIGALRM)}
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, MUTANT_WALL_SECONDS)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@pytest.fixture(scope="module", autouse=True)
def fuzz_limits():
    patch = pytest.MonkeyPatch()
    for name, value in FUZZ_LIMITS.items():
        patch.setenv(name, value)
    yield
    patch.undo()


def _assert_one_line(result, path: Path, raw: bytes, what: str) -> None:
    output = result.output or ""
    lines = output.strip().splitlines()
    assert len(lines) == 1, f"{what}: {output}"
    m = re.match(rf"^{re.escape(str(path))}{ONE_LINE}", lines[0])
    assert m, f"{what}: {output}"
    assert 1 <= int(m[1]) <= raw.count(b"\n") + 1, f"{what}: line {m[1]} outside the file: {output}"


CASES = {"check": 0, "run": 0, "check_65": 0, "check_0": 0}  # fuzz cases run in this session


def _check_mutant(tmp_path, data) -> None:
    """One mutant through `sphfem check`: exit 0, or 65 with one located line; never a traceback or a hang."""
    deck = data.draw(st.sampled_from(WEIGHTED), label="deck")
    raw, what = _mutant_bytes(data, deck)
    mutated = tmp_path / deck.name
    mutated.write_bytes(raw)
    CASES["check"] += 1
    try:
        with _budget(MUTANT_SECONDS, what):
            result = CliRunner().invoke(main, ["check", str(mutated)])
    except MutantTimeout:
        # a first check of a kind may compile its kernels (an empty or stale numba cache on a loaded
        # machine took longer than the budget); a second try loads them, and a hang hangs again
        with _budget(MUTANT_SECONDS, what):
            result = CliRunner().invoke(main, ["check", str(mutated)])
    output = result.output or ""
    assert "Traceback" not in output, f"{what}: {output}"
    assert result.exception is None or isinstance(result.exception, SystemExit), f"{what}: {result.exception!r}"
    assert result.exit_code in (0, 65), f"{what}: exit {result.exit_code}: {output}"
    CASES[f"check_{result.exit_code}"] += 1
    if result.exit_code == 65:
        _assert_one_line(result, mutated, raw, what)


@settings(max_examples=FUZZ_CHECK_CASES, deadline=None, database=None, print_blob=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_decks_exit_0_or_65(tmp_path, data):
    _check_mutant(tmp_path, data)


@pytest.mark.validation
@settings(max_examples=FUZZ_CHECK_CASES_LONG, deadline=None, database=None, print_blob=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(data=st.data())
def test_many_mutated_decks_exit_0_or_65(tmp_path, data):
    _check_mutant(tmp_path, data)


def _non_finite(folder: Path) -> list[str]:
    """Output files holding a NaN or an infinity: history CSVs and every float dataset of the HDF5 files."""
    import h5py

    bad = []
    for csv in sorted(folder.rglob("*.csv")):
        rows = csv.read_text(encoding="utf-8").splitlines()[1:]
        if rows and not np.all(np.isfinite(np.array([[float(c) for c in r.split(",")] for r in rows]))):
            bad.append(csv.name)
    for h5 in sorted(folder.rglob("*.h5")):
        with h5py.File(h5, "r") as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and not np.all(np.isfinite(obj[()])):
                    bad.append(f"{h5.name}:{name}")
            f.visititems(visit)
    return bad


@settings(max_examples=40, deadline=None, database=None, print_blob=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_decks_run_or_exit_65(tmp_path, data, monkeypatch_steps):
    deck = data.draw(st.sampled_from(RUN_DECKS), label="deck")
    raw, what = _mutant_bytes(data, deck)
    mutated = tmp_path / deck.name
    mutated.write_bytes(raw)
    out = tmp_path / "out"
    CASES["run"] += 1
    result = CliRunner().invoke(main, ["run", "-q", str(mutated), "-o", str(out), "--overwrite"])  # one folder
    output = result.output or ""
    assert "Traceback" not in output, output
    assert result.exception is None or isinstance(result.exception, SystemExit), f"{what}: {result.exception!r}"
    assert result.exit_code in (0, 3, 65), f"{what}: exit {result.exit_code}: {output}"
    lines = output.strip().splitlines()
    if result.exit_code == 65:
        _assert_one_line(result, mutated, raw, what)
    if result.exit_code == 3:
        assert len(lines) == 1 and lines[0].startswith("run stopped: "), output
        assert (out / "diagnostics.txt").read_text().startswith("guard: ")
    if result.exit_code == 0:
        assert not _non_finite(out), f"{what}: exit 0 with non-finite output {_non_finite(out)}"


@pytest.fixture(scope="module")
def monkeypatch_steps():
    """Cap every fuzzed run at RUN_STEP_CAP steps (a mutated end_time may ask for billions)."""
    from sphfem_cli.solver import explicit

    patch = pytest.MonkeyPatch()
    original = explicit.Simulation.step

    def capped(self, stop=None):
        if self.state.step >= RUN_STEP_CAP:
            raise explicit.RunStopped(f"fuzz step cap {RUN_STEP_CAP} reached", "fuzz_cap")
        original(self, stop)

    patch.setattr(explicit.Simulation, "step", capped)
    yield
    patch.undo()


def test_fuzz_case_count():
    """Reports how many fuzz cases this session ran (run with -s to see it); all when the check test ran."""
    print(f"deck fuzzing: {CASES['check']} check cases ({CASES['check_65']} exit 65, {CASES['check_0']} pass), "
          f"{CASES['run']} run cases")
    assert CASES["check"] == 0 or CASES["check"] >= FUZZ_CHECK_CASES


def test_every_shipped_deck_is_a_base():
    assert SHIPPED and set(SHIPPED) <= set(WEIGHTED)


def test_emitter_round_trips_every_base():
    """The mutants' writer (fuzz_yaml.emit) writes each base back to the same tree."""
    for deck, tree in BASES.items():
        again = loader.loads(emit(tree), str(deck))[0]
        assert again == tree, deck


def test_model_too_large_is_refused_before_allocation(tmp_path):
    deck = tmp_path / "huge.yaml"
    deck.write_text("""
dimension: 3
control: {end_time: 1.0}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  cube: {material: steel, section: solid, geometry: {box: {min: [0, 0, 0], max: [1, 1, 1], divisions: [5000, 5000, 5000]}}}
""")
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 65
    assert re.search(r":9:\d+: parts\.cube\.geometry: the model needs about \d+\.\d GiB, more than the", result.output)
