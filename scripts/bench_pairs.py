#!/usr/bin/env python3
"""Paired comparison of two methods over one or more `pllvo bench` outputs.

    python3 scripts/bench_pairs.py --a pllvo --b pllvo-mnn OUT1/bench.csv OUT2/bench.csv ...

Every sequence row where both methods have an ATE (and no failed run) is one pair; the same
sequence name in two csv files (two suites rendered with other seeds) is two pairs. Prints one
line per pair, then over all pairs: mean ATE (% of path and metres) of each method, how many
pairs each wins, the median paired difference (a - b, % of path), and a bootstrap 95 % interval
of the mean difference (resampling pairs; fixed seed). A method ahead on the mean with an
interval that straddles zero is a tie, not a win. Standard library only.
"""
import argparse
import csv
import random
import statistics
import sys
from pathlib import Path


def read_rows(path):
    rows = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("failed") not in (None, "", "0") or not r.get("ate_percent"):
                continue
            rows[(r["sequence"], r["method"])] = (float(r["ate_percent"]), float(r["ate_rmse_m"]))
    return rows


def bootstrap_interval(diffs, resamples=10000, seed=0):
    rng = random.Random(seed)
    means = sorted(statistics.fmean(rng.choices(diffs, k=len(diffs))) for _ in range(resamples))
    return means[int(0.025 * resamples)], means[int(0.975 * resamples) - 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", nargs="+", type=Path, help="bench.csv files")
    ap.add_argument("--a", required=True, help="method A (its ATE minus B's is reported)")
    ap.add_argument("--b", required=True, help="method B")
    args = ap.parse_args()

    pairs = []
    for path in args.csv:
        if not path.is_file():
            sys.exit(f"{path}: no such file")
        rows = read_rows(path)
        for (seq, method), a in sorted(rows.items()):
            if method != args.a or (seq, args.b) not in rows:
                continue
            pairs.append((path.parent.name, seq, a, rows[(seq, args.b)]))
    if not pairs:
        sys.exit(f"no sequence has both {args.a} and {args.b}")

    print(f"{'bench':28s} {'sequence':20s} {args.a + ' %':>12s} {args.b + ' %':>12s} {'a - b':>8s}")
    for bench, seq, a, b in pairs:
        print(f"{bench:28s} {seq:20s} {a[0]:12.2f} {b[0]:12.2f} {a[0] - b[0]:+8.2f}")
    diffs = [a[0] - b[0] for _, _, a, b in pairs]
    lo, hi = bootstrap_interval(diffs)
    wins_a = sum(d < 0 for d in diffs)
    wins_b = sum(d > 0 for d in diffs)
    n = len(pairs)
    print(f"\n{n} pairs")
    for name, k in ((args.a, 2), (args.b, 3)):
        pct = statistics.fmean(p[k][0] for p in pairs)
        m = statistics.fmean(p[k][1] for p in pairs)
        print(f"  {name:14s} mean ATE {pct:.3f} % of the path, {m:.4f} m")
    print(f"  lower ATE: {args.a} on {wins_a}, {args.b} on {wins_b}, equal on {n - wins_a - wins_b}")
    print(f"  {args.a} - {args.b}: mean {statistics.fmean(diffs):+.3f} %, median {statistics.median(diffs):+.3f} %, "
          f"bootstrap 95 % interval of the mean [{lo:+.3f}, {hi:+.3f}] %")


if __name__ == "__main__":
    main()
