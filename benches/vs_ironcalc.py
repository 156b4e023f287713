#!/usr/bin/env python3
"""Open + full computation of a generated workbook by IronCalc and by ncsheet, in turns.

    pip install ironcalc==0.9.1 openpyxl
    python3 benches/gen_workbooks.py --out /tmp/wb grid-100000
    cargo build --release --bin ncsheet-bench-document
    python3 benches/vs_ironcalc.py /tmp/wb/grid-100000.xlsx --runs 5

Each run is a process of its own: IronCalc through its Python binding (`load_from_xlsx`,
then `evaluate`; the last cell checked against `gen_workbooks.py --spec`), then
`ncsheet-bench-document FILE`, whose open is read from its table (the library's `Document`:
read, import, full computation, the last cell checked). The two alternate, so that a busy
machine weighs on both alike; the medians and their ratio are printed.
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
BENCH = HERE.parent / "target" / "release" / "ncsheet-bench-document"


def spec(name):
    """Last cell and its value after the full computation, from gen_workbooks.py."""
    out = subprocess.run([sys.executable, str(HERE / "gen_workbooks.py"), "--spec", name],
                         capture_output=True, text=True, check=True).stdout.split()
    return out[0], float(out[3])


def ironcalc_child(path):
    import ironcalc  # noqa: PLC0415 (only the child needs it)
    # IronCalc's reader prints a line to stdout for each formula cell without a cached
    # value (a million here): sent to /dev/null, so that no terminal is timed.
    saved = os.dup(1)
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
    start, cpu = time.perf_counter(), time.process_time()
    model = ironcalc.load_from_xlsx(path, "en", "UTC")
    model.evaluate()
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    os.dup2(saved, 1)
    cell, want = spec(pathlib.Path(path).stem)
    sheet = model.get_worksheets_properties()[0]["name"]
    got = model.get_cell_value_by_ref(f"{sheet}!{cell}")
    if abs(got - want) > 1e-9 * max(abs(want), 1.0):
        sys.exit(f"IronCalc: {cell} is {got}, gen_workbooks.py --spec says {want}")
    print(seconds, cpu)


def ironcalc_run(path):
    """Wall-clock and CPU seconds of IronCalc's load and evaluation."""
    out = subprocess.run([sys.executable, __file__, "--ironcalc-child", path],
                         capture_output=True, text=True, check=True)
    wall, cpu = out.stdout.split()[-2:]
    return float(wall), float(cpu)


def ncsheet_run(bench, path):
    """Wall-clock and CPU seconds of ncsheet's open (both of the reader's threads)."""
    out = subprocess.run([str(bench), path], capture_output=True, text=True, check=True).stdout
    row = out.strip().splitlines()[-1]  # | name | 0.93 s (1.02 s) | …
    wall, _, cpu = row.split("|")[2].split()[:3]
    return float(wall), float(cpu.strip("("))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("file")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--bench", default=os.environ.get("NCSHEET_BENCH_DOCUMENT", str(BENCH)))
    parser.add_argument("--ironcalc-child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.ironcalc_child:
        return ironcalc_child(args.file)
    ours, theirs = [], []
    for _ in range(args.runs):
        theirs.append(ironcalc_run(args.file))
        ours.append(ncsheet_run(args.bench, args.file))
        print(f"IronCalc {theirs[-1][0]:.2f} s (CPU {theirs[-1][1]:.2f} s), "
              f"ncsheet {ours[-1][0]:.2f} s (CPU {ours[-1][1]:.2f} s)", flush=True)
    for i, what in enumerate(["wall-clock", "CPU"]):
        a, b = statistics.median(r[i] for r in ours), statistics.median(r[i] for r in theirs)
        print(f"{what}, medians of {args.runs}: ncsheet {a:.3f} s, IronCalc {b:.3f} s: ratio {a / b:.3f}")


if __name__ == "__main__":
    main()
