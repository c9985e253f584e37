"""gearcalc benchmark: start-up, per-design compute, batches and sweeps on the machine it runs on.

Usage:  python benchmarks/bench.py [--out benchmarks/results.csv] [--repeat 7] [--loop 1000] [--quick]

Run it with the interpreter of an environment where gearcalc is installed as users install it
(``pip install .``): the subprocess figures time that environment's ``gearcalc`` command. An editable
install (``pip install -e``) adds its import hook to every start-up; the header line says which it is.

Measures (wall times of subprocesses are medians of --repeat runs; in-process times are medians of up to
10 x --repeat calls, within 0.25 s per figure, after a warm-up call):
* start-up: ``python -c pass``, ``gearcalc --help`` and one design of each kind, end to end (CSV out);
* per-design compute in process for every shipped config, per calculator and model level, at --tol 1e-6;
* batch: 1000 generated design files of each kind in one ``gearcalc run DIR`` call, against one design in
  one call; and, for rows, against a shell loop of --loop single calls;
* sweeps: points per second of ``gearcalc sweep`` end to end (CSV to a file) for each kind, and of the
  rows sweep hook in process.
It prints a table (with the issue-6 target of each figure and whether it is met) and writes it as CSV.
``--quick`` uses 3 repeats, 200 batch files and a 50-call shell loop (a smoke run, not for the README).
"""
from __future__ import annotations

import argparse
import csv
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"
_SCRIPT = Path(sys.executable).with_name("gearcalc")
GEARCALC = [str(_SCRIPT)] if _SCRIPT.is_file() else [sys.executable, "-m", "gearcalc"]
"""The command a user types: the ``gearcalc`` console script of this interpreter's environment (what
``pip install .`` writes next to ``python``), else ``python -m gearcalc``."""


def install_kind() -> str:
    """How gearcalc is installed: an editable install pays an import-hook finder at every start-up."""
    from importlib import metadata

    try:
        dist = metadata.distribution("gearcalc")
    except metadata.PackageNotFoundError:
        return "not installed (source tree)"
    direct = dist.read_text("direct_url.json") or ""
    return "editable (pip install -e; its import hook adds start-up time)" if '"editable": true' in direct \
        else "regular (pip install .)"

# One design file per kind for the start-up and batch figures, and the key the batch generator varies.
BATCH = {
    "rows": ("rows_fig3_n3_nw3_B2.4.toml", "relative_width", lambda k, n: 2.0 + 0.8 * k / max(n - 1, 1)),
    "zstk": ("zstk_merko_example.toml", "radial_N", lambda k, n: 5000.0 + 10000.0 * k / max(n - 1, 1)),
    "pins": ("pins_paper_cyc_u10_fixed.toml", "torque_Nm", lambda k, n: 50.0 + 100.0 * k / max(n - 1, 1)),
}
SWEEPS = {
    "rows": ("rows_fig3_n3_nw3_B2.4.toml", ["rows.count=1,2,3,4", "rows.planets_per_row=3,4,5",
                                            "rows.relative_width=0.5:3.0:0.0001"]),
    "zstk": ("zstk_merko_example.toml", ["load.radial_N=1000:11000:1", "load.direction_deg=0,10"]),
    "pins": ("pins_paper_cyc_u10_fixed.toml", ["load.torque_Nm=10:20000:2", "friction.sliding=0.05,0.1"]),
}


ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
"""Subprocesses run as a user's do: with cached bytecode (a sandbox that sets PYTHONDONTWRITEBYTECODE would
otherwise recompile every gearcalc module on every call, ~30 ms)."""


def wall(cmd, repeat: int, shell: bool = False) -> float:
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False, shell=shell, env=ENV)
    times = []  # after one warm-up run (bytecode cache, file cache)
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False, shell=shell,
                       env=ENV)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def in_process(design, calc, options, repeat: int, budget: float = 0.25) -> float:
    """Median compute time after a warm-up call: at least 10 * repeat calls, or as many as fit in ``budget``
    seconds (a median of many cheap calls is robust against a moment of load on a shared machine)."""
    calc.compute(design, options)  # warm-up
    times = []
    start = time.perf_counter()
    while len(times) < 3 or (len(times) < 10 * repeat and time.perf_counter() - start < budget):
        t = time.perf_counter()
        calc.compute(design, options)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def generate(kind: str, folder: Path, count: int) -> None:
    name, key, value = BATCH[kind]
    text = (CONFIGS / name).read_text()
    for k in range(count):
        body, n = re.subn(rf"^{key} = [^#\n]*", f"{key} = {value(k, count)!r}  ", text, flags=re.M)
        assert n == 1, (kind, key)
        (folder / f"{kind}_{k:05d}.toml").write_text(body)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results.csv"))
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--batch", type=int, default=1000, help="design files per batch")
    ap.add_argument("--loop", type=int, default=1000, help="single calls in the shell loop (rows)")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    if args.quick:
        args.repeat, args.batch, args.loop = 3, 200, 50

    from gearcalc import design as dmod
    from gearcalc import registry
    from gearcalc.calculator import Options

    rows: list[tuple] = []

    def add(group, what, kl, ms, note="", target="", met=""):
        rows.append((group, what, kl, ms, note, target, met))
        print(f"{group:8} {kl:24} {ms:12.3f}  {what} {note} {target} {met}".rstrip(), flush=True)

    print(f"# {platform.node()} {platform.machine()} {platform.processor() or ''} python "
          f"{platform.python_version()}, {os.cpu_count()} cpus")
    print(f"# command: {' '.join(GEARCALC)}; install: {install_kind()}")
    base = wall([sys.executable, "-c", "pass"], args.repeat)
    add("startup", "python -c pass", "", base * 1e3)
    t = wall(GEARCALC + ["--help"], args.repeat)
    add("startup", "gearcalc --help", "", t * 1e3, f"{t / base:.2f}x python", "<= 6x python", t <= 6 * base)
    one = {}
    for kind, (name, _, _) in BATCH.items():
        t = wall(GEARCALC + [kind, str(CONFIGS / name), "--format", "csv"], args.repeat)
        one[kind] = t
        add("startup", f"gearcalc {kind} {name} (one design, csv)", kind, t * 1e3, "", "<= 150 ms", t <= 0.150)

    # per-design compute, every shipped config at every level
    for f in sorted(CONFIGS.glob("*.toml")):
        try:
            d = dmod.load(str(f))
        except dmod.InputError:
            continue
        calc = registry.get(d.kind)
        for level in calc.models:
            try:
                t = in_process(d, calc, Options(tol=1e-6, model=level), args.repeat)
            except Exception as exc:  # a level that does not apply to this design
                add("compute", f.name, f"{d.kind}:{level}", float("nan"), f"n/a: {str(exc)[:50]}")
                continue
            target = ""
            if (d.kind, level) in (("pins", "ideal"), ("rows", "stepwise")) or (
                    d.kind == "zstk" and level == "equilibrium" and "envelope" not in f.name):
                target = "<= 1 ms"
            add("compute", f.name, f"{d.kind}:{level}", t * 1e3, "", target, (t <= 1e-3) if target else "")

    # batches: N files in one call against one design in one call (and, for rows, a shell loop)
    work = Path(tempfile.mkdtemp(prefix="gearcalc-bench-"))
    try:
        for kind in BATCH:
            folder = work / kind
            folder.mkdir()
            generate(kind, folder, args.batch)
            t = wall(GEARCALC + ["run", str(folder), "--format", "csv", "-o", str(work / f"{kind}.csv")],
                     max(1, args.repeat // 2))
            ratio = t / one[kind]
            add("batch", f"{args.batch} {kind} designs in one call", kind, t * 1e3,
                f"{ratio:.2f}x one design; {t / args.batch * 1e3:.3f} ms/design", "<= 5x one design", ratio <= 5)
            if kind == "rows":
                files = sorted(folder.glob("*.toml"))[:args.loop]
                listing = work / "list.txt"
                listing.write_text("\n".join(str(p) for p in files) + "\n")
                cmd = (f'while read -r f; do {" ".join(map(shlex.quote, GEARCALC))} rows "$f" --format csv; done '
                       f'< "{listing}" > /dev/null 2>&1')
                t_loop = wall(cmd, 1, shell=True)
                per_loop = t_loop / len(files)
                add("batch", f"shell loop of {len(files)} single calls", kind, t_loop * 1e3,
                    f"{per_loop * 1e3:.1f} ms/call; one batch call is {per_loop * args.batch / t:.0f}x faster "
                    f"per design")
        # sweeps end to end
        for kind, (name, vary) in SWEEPS.items():
            cmd = GEARCALC + ["sweep", str(CONFIGS / name), "--format", "csv", "-o", str(work / "sweep.csv")]
            for v in vary:
                cmd += ["--vary", v]
            t = wall(cmd, max(1, args.repeat // 3))
            with open(work / "sweep.csv") as fh:
                points = sum(1 for _ in fh) - 1
            target = ">= 1e5 points/s" if kind == "rows" else ""
            add("sweep", f"{points} points, csv to a file", kind, t * 1e3, f"{points / t:,.0f} points/s", target,
                (points / t >= 1e5) if target else "")
    finally:
        shutil.rmtree(work, ignore_errors=True)

    # the rows sweep hook in process (no start-up, no CSV text)
    from gearcalc import grid as sw

    raw = dmod.read_toml(str(CONFIGS / SWEEPS["rows"][0]))
    axes = sw.parse_vary(SWEEPS["rows"][1])
    points = sw.grid_points(axes)
    base_design = dmod.validate(dict(raw), "bench")
    calc = registry.get("rows")
    calc.sweep(base_design, raw, axes, points[:100], Options())
    t0 = time.perf_counter()
    calc.sweep(base_design, raw, axes, points, Options())
    t = time.perf_counter() - t0
    add("sweep", f"{len(points)} points, rows sweep hook in process", "rows", t * 1e3,
        f"{len(points) / t:,.0f} points/s")

    header = ("group", "what", "kind:level", "time_ms", "note", "target", "met")
    with open(args.out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
