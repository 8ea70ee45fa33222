"""Hostile decks through the real `sphfem` command, independent of tests/unit/test_deck_fuzz.py.

The suite's fuzzer mutates the parsed tree of a deck and dumps it back; this script mutates the
*text* of the shipped decks (decks/*.yaml): numbers swapped for extremes, lines deleted, duplicated
or re-indented, names renamed everywhere (to Unicode) or in one place, flow vectors lengthened or
shortened, bytes injected, the file truncated, YAML tags, alias bombs, deep nesting, huge files, and
mesh files that are FIFOs, directories or corrupt. Each mutant goes through `sphfem check` in a
subprocess with a 10 s limit; a sample of those that pass is run for a few stable steps (end_time
cut to ~20 steps), and the run's outputs are scanned for non-finite values.

Acceptance (issue 13): every mutant either exits 65 with one line ``file:line:col: path: message``
or passes check and then runs with exit 0 or 3; no traceback, no exit 1, no check over 10 s, no
exit-0 run with a non-finite value in an output file.

    python benchmarks/hostile_decks.py --mutants 300 --runs 30 --seed 1 [--keep DIR]
"""
from __future__ import annotations

import argparse
import collections
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DECKS = sorted((ROOT / "decks").glob("*.yaml"))
ONE_LINE = re.compile(r"^.+:\d+:\d+: .+: .+$")  # file:line:col: path: message (a path may hold spaces)
NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d*)?([eE][-+]?\d+)?(?![\w.])")
FLOW_VECTOR = re.compile(r"\[([^\[\]\n]*,[^\[\]\n]*)\]")
NAME_VALUE = re.compile(r"(\b(?:material|section|part|eos|set|curve|structure|fluid|surface|nodes|"
                        r"slave|master|parts)\s*:\s*)([A-Za-z_][\w]*)")
EXTREMES = ["1e308", "-1e308", "1e-300", "-0.0", "0", ".nan", ".inf", "-.inf", "5e-324", "1e30",
            "-1", "123456789012345678901234567890", "0x7fffffffffffffff", "2e-308", "1e-30"]
UNICODE = ["名前", "🔥", "Ünïcödé", "a b", "x\u200by", "ɸ_1", "‮rtl"]
TAGS = ["!!python/object/apply:os.system ['echo pwned']", "!!binary aGVsbG8=", "!custom 3",
        "!!timestamp 2001-12-14", "!!set {a, b}", "!!omap [a: 1]", "!!float abc", "!!int 1.5"]


def _lines(text):
    lines = [i for i, line in enumerate(text.splitlines()) if line.strip() and not line.lstrip().startswith("#")]
    return lines or [0]


def swap_number(rng, text):
    hits = list(NUMBER.finditer(text))
    if not hits:
        return text, "no number"
    m = rng.choice(hits)
    new = rng.choice(EXTREMES)
    return text[:m.start()] + new + text[m.end():], f"number {m.group()} -> {new}"


def delete_line(rng, text):
    lines = text.splitlines(keepends=True) or [""]
    i = rng.choice(_lines(text))
    return "".join(lines[:i] + lines[i + 1:]), f"delete line {i + 1}"


def duplicate_line(rng, text):
    lines = text.splitlines(keepends=True) or [""]
    i = rng.choice(_lines(text))
    return "".join(lines[:i + 1] + [lines[i]] + lines[i + 1:]), f"duplicate line {i + 1}"


def reindent_line(rng, text):
    lines = text.splitlines(keepends=True) or [""]
    i = rng.choice(_lines(text))
    pad = rng.choice(["\t", " ", "   ", ""])
    lines[i] = pad + lines[i].lstrip(" ") if pad else lines[i].lstrip(" ")
    return "".join(lines), f"reindent line {i + 1} with {pad!r}"


def rename_everywhere(rng, text):
    hits = list(NAME_VALUE.finditer(text))
    if not hits:
        return text, "no name"
    old = rng.choice(hits).group(2)
    new = rng.choice(UNICODE[:3]) + rng.choice(["", "_2"])
    return re.sub(rf"(?<![\w.]){re.escape(old)}(?![\w])", new, text), f"rename {old} -> {new} everywhere"


def rename_once(rng, text):
    hits = list(NAME_VALUE.finditer(text))
    if not hits:
        return text, "no name"
    m = rng.choice(hits)
    new = rng.choice(UNICODE + ["nosuch", "'1'", "null", "[]"])
    return text[:m.start(2)] + new + text[m.end(2):], f"name {m.group(2)} -> {new} once"


def vector_length(rng, text):
    hits = list(FLOW_VECTOR.finditer(text))
    if not hits:
        return text, "no vector"
    m = rng.choice(hits)
    items = [s.strip() for s in m.group(1).split(",")]
    if rng.random() < 0.5 and len(items) > 1:
        items = items[:-1]
    else:
        items = items + [rng.choice(["0.0", "1.0", items[-1]])]
    return text[:m.start()] + "[" + ", ".join(items) + "]" + text[m.end():], f"vector {m.group()} -> {items}"


def inject_bytes(rng, text):
    pos = rng.randrange(max(len(text), 1))
    junk = rng.choice(["\x00", "\x07", "\ufeff", "\x1b[2J", "\udcff", "\x85", "\u2028", "\x80\x81"])
    return text[:pos] + junk + text[pos:], f"bytes {junk!r} at {pos}"


def truncate(rng, text):
    pos = rng.randrange(1, max(len(text), 2))
    return text[:pos], f"truncate at {pos}"


def tag_value(rng, text):
    hits = list(re.finditer(r":[ \t]+([^\s{}\[\],#][^\n,}#]*)", text))
    if not hits:
        return text, "no value"
    m = rng.choice(hits)
    tag = rng.choice(TAGS)
    return text[:m.start(1)] + tag + text[m.end(1):], f"tag {tag}"


def alias_bomb(rng, text):
    levels = rng.randint(5, 9)
    bomb = ["bomb_0: &b0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for k in range(1, levels + 1):
        bomb.append(f"bomb_{k}: &b{k} [" + ", ".join([f"*b{k - 1}"] * 10) + "]")
    key = rng.choice(["title", "curves", "zzz"])
    where = rng.choice(["top", "title"])
    if where == "title":
        body = "\n".join(bomb[:-1]) + f"\n{key}: *b{levels - 1}\n"
        return body + re.sub(r"^title:.*$", "", text, flags=re.M), f"alias bomb {levels} levels at {key}"
    return text + "\n" + "\n".join(bomb) + "\n", f"alias bomb {levels} levels at top"


def merge_bomb(rng, text):
    levels = rng.randint(5, 8)
    lines = ["m_0: &m0 {a: 1, b: 2}"]
    for k in range(1, levels + 1):
        lines.append(f"m_{k}: &m{k} {{<<: [" + ", ".join([f"*m{k - 1}"] * 10) + "]}")
    return text + "\n" + "\n".join(lines) + "\n", f"merge bomb {levels} levels"


def deep_nesting(rng, text):
    depth = rng.choice([1000, 5000, 20000])
    style = rng.choice(["flow_list", "flow_map", "block"])
    if style == "flow_list":
        value = "[" * depth + "1" + "]" * depth
    elif style == "flow_map":
        value = "{a: " * depth + "1" + "}" * depth
    else:
        value = "\n" + "".join(" " * (i + 1) + "a:\n" for i in range(min(depth, 3000))) + " " * 3001 + "1"
    return text + f"\ndeep: {value}\n", f"nesting {depth} {style}"


def huge(rng, text):
    what = rng.choice(["comments", "list", "string"])
    if what == "comments":
        return text + ("# " + "x" * 78 + "\n") * 375_000, "30 MB of comments"
    if what == "list":
        return text + "\nbig: [" + "1, " * 3_000_000 + "1]\n", "9 MB flow list"
    return text.replace("title:", "title: " + "x" * 20_000_000 + "\nold_title:", 1), "20 MB title"


OPERATORS = [(swap_number, 20), (delete_line, 10), (duplicate_line, 5), (reindent_line, 5),
             (rename_everywhere, 8), (rename_once, 8), (vector_length, 10), (inject_bytes, 5),
             (truncate, 4), (tag_value, 5), (alias_bomb, 3), (merge_bomb, 2), (deep_nesting, 3), (huge, 1)]


def mesh_file_mutants(work: Path):
    """Solid decks whose part reads a mesh file that is a FIFO, a directory, /dev/zero or corrupt."""
    base = (ROOT / "decks" / "cantilever_3d.yaml").read_text()
    vtu_good = (ROOT / "tests" / "data" / "hex_2x1x1_flipped.vtu").read_bytes()
    targets = {}
    fifo = work / "mesh.fifo"
    if not fifo.exists():
        os.mkfifo(fifo)
    targets["fifo"] = fifo
    (work / "meshdir.vtu").mkdir(exist_ok=True)
    targets["directory"] = work / "meshdir.vtu"
    targets["dev_zero"] = Path("/dev/zero")
    for name, data in {"corrupt.vtu": vtu_good[: len(vtu_good) // 2], "garbage.vtu": b"<VTKFile>\x00\xff",
                       "empty.msh": b"", "text.inp": b"*NODE\n1, a, b, c\n*ELEMENT, TYPE=C3D8\n1, 1\n",
                       "random.msh": bytes(random.Random(3).randrange(256) for _ in range(4000))}.items():
        (work / name).write_bytes(data)
        targets[name] = work / name
    out = []
    for label, path in targets.items():
        text = re.sub(r"geometry:\s*\{box:.*\}\}", f"geometry: {{file: {{file: {path}}}}}", base, count=1)
        if text == base:
            text = re.sub(r"(geometry:\s*\n\s+)box:", rf"\1file: {{file: {path}}}\n      old_box:", base, count=1)
        out.append((text, f"mesh file {label}"))
    return out


def classify(proc_rc, output, elapsed, limit):
    if elapsed >= limit:
        return "over_10s"
    if "Traceback" in output:
        return "traceback"
    if proc_rc == 1:
        return "exit_1"
    if proc_rc == 65:
        lines = output.strip().splitlines()
        return "exit_65_one_line" if len(lines) == 1 and ONE_LINE.match(lines[0]) else "exit_65_bad_message"
    if proc_rc == 0:
        return "pass"
    return f"exit_{proc_rc}"


def sphfem(args, timeout):
    start = time.monotonic()
    env = dict(os.environ, NUMBA_NUM_THREADS=os.environ.get("NUMBA_NUM_THREADS", "1"))
    try:
        p = subprocess.run([str(Path(sys.executable).with_name("sphfem")), *args], capture_output=True,
                           timeout=timeout, env=env)
        rc, out = p.returncode, (p.stdout + p.stderr).decode("utf-8", "replace")
    except subprocess.TimeoutExpired as exc:
        rc, out = -9, ((exc.stdout or b"") + (exc.stderr or b"")).decode("utf-8", "replace")
    return rc, out, time.monotonic() - start


def non_finite_outputs(folder: Path) -> list[str]:
    """Output files (CSV histories, HDF5 datasets) that hold a NaN or an infinity."""
    import h5py
    import numpy as np

    bad = []
    for csv in folder.glob("*.csv"):
        rows = csv.read_text(encoding="utf-8").splitlines()[1:]
        for row in rows:
            for cell in row.split(","):
                try:
                    if not np.isfinite(float(cell)):
                        bad.append(csv.name)
                        break
                except ValueError:
                    pass
            if bad and bad[-1] == csv.name:
                break
    for h5 in folder.glob("*.h5"):
        with h5py.File(h5, "r") as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and not np.all(np.isfinite(obj[()])):
                    bad.append(f"{h5.name}:{name}")
            f.visititems(visit)
    return bad


def capped(text: str, dt: float) -> str:
    """The deck with end_time cut to about 20 stable steps (the first end_time key)."""
    return re.sub(r"end_time:\s*[-+.\w]+", f"end_time: {20 * dt:.6e}", text, count=1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mutants", type=int, default=300)
    ap.add_argument("--runs", type=int, default=30, help="passing mutants run for ~20 steps")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--limit", type=float, default=10.0, help="seconds a check may take")
    ap.add_argument("--keep", type=Path, default=None, help="keep the failing mutants here")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    work = Path(tempfile.mkdtemp(prefix="hostile_"))
    ops, weights = zip(*OPERATORS)
    mutants = mesh_file_mutants(work)
    while len(mutants) < args.mutants:
        deck = rng.choice(DECKS)
        text = deck.read_text(encoding="utf-8")
        what = []
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            op = rng.choices(ops, weights)[0]
            text, w = op(rng, text)
            what.append(w)
        mutants.append((text, f"{deck.name}: " + "; ".join(what)))
    counts = collections.Counter()
    slowest = (0.0, "")
    failures = []
    passing = []
    for i, (text, what) in enumerate(mutants):
        path = work / f"m{i:04d}.yaml"
        path.write_bytes(text.encode("utf-8", "surrogateescape").replace(b"\xed\xb3\xbf", b"\xff"))
        rc, out, elapsed = sphfem(["check", str(path)], timeout=args.limit)
        if elapsed >= args.limit:  # once more: on a loaded machine a slow check is not yet a hang
            rc, out, elapsed = sphfem(["check", str(path)], timeout=args.limit)
        slowest = max(slowest, (elapsed, what))
        kind = classify(rc, out, elapsed, args.limit)
        counts[kind] += 1
        if kind == "pass":
            dt = re.search(r"stable time step (\S+)", out)
            passing.append((path, text, what, float(dt.group(1)) if dt else None))
        elif kind != "exit_65_one_line":
            failures.append((kind, what, path, out.strip()[-400:]))
    run_counts = collections.Counter()
    for path, text, what, dt in rng.sample(passing, min(args.runs, len(passing))):
        run_deck = path.with_name(path.stem + "_run.yaml")
        run_deck.write_text(capped(text, dt) if dt else text, encoding="utf-8")
        out_dir = work / (path.stem + "_out")
        rc, out, elapsed = sphfem(["run", "-q", str(run_deck), "-o", str(out_dir)], timeout=300)
        kind = {0: "run_exit_0", 3: "run_exit_3", 65: "run_exit_65"}.get(rc, f"run_exit_{rc}")
        if "Traceback" in out:
            kind = "run_traceback"
        if rc == 0 and out_dir.exists() and (bad := non_finite_outputs(out_dir)):
            kind = "run_exit_0_non_finite"
            out += f" non-finite in {bad[:3]}"
        run_counts[kind] += 1
        if kind not in ("run_exit_0", "run_exit_3"):
            failures.append((kind, what, run_deck, out.strip()[-400:]))
    print(f"{len(mutants)} mutants through `sphfem check` (limit {args.limit:g} s, a slow one tried twice; "
          f"slowest {slowest[0]:.1f} s: {slowest[1][:80]}):")
    for kind, n in sorted(counts.items()):
        print(f"  {kind}: {n}")
    print(f"{sum(run_counts.values())} passing mutants run (~20 steps):")
    for kind, n in sorted(run_counts.items()):
        print(f"  {kind}: {n}")
    for kind, what, path, out in failures:
        print(f"FAIL {kind}: {what} [{path}]\n    {out}")
        if args.keep:
            args.keep.mkdir(parents=True, exist_ok=True)
            if path.stat().st_size < 2_000_000:
                shutil.copy(path, args.keep / path.name)
    shutil.rmtree(work, ignore_errors=True) if not failures else None
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
