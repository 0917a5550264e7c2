#!/usr/bin/python3
"""Summaries of the scratch output of increment_breakdown.patch (bench/patches/README.md).

  increment_breakdown.py boxes FILE   per-box lines (PKM_DUMP=1): leaves, boxes split, and why (nominal or increase)
  increment_breakdown.py bounds FILE  per full bound (PKM_DUMP2=1): the parts of the geometry increase's bound,
                                      relative to the component's target (means and 10/50/90% quantiles)
"""
import collections
import sys

INF = float('inf')


def quantiles(values):
    values = sorted(values)
    n = len(values)
    return sum(values) / n, values[n // 10], values[n // 2], values[9 * n // 10]


def boxes(path):
    kinds = collections.Counter()
    by_depth = collections.defaultdict(collections.Counter)
    for line in open(path):
        if not line.startswith('BOX'):
            continue
        t = line.split()
        depth, active = int(t[1]), int(t[3])
        v = list(map(float, t[4:16]))
        nominal = list(map(float, t[16:22]))
        upper = [v[2 * k] for k in range(6)]
        failing = [k for k in range(6) if active >> k & 1 and upper[k] > 1]
        if not failing:
            kind = 'leaf'
        elif any(upper[k] == INF for k in failing):
            kind = 'no bound'
        elif any(nominal[k] > 1 for k in failing):
            kind = 'nominal misses'
        elif all(nominal[k] > 0 for k in failing):
            kind = 'increase misses'
        else:
            kind = 'other'
        kinds[kind] += 1
        by_depth[depth][kind] += 1
    print(dict(kinds))
    for d in sorted(by_depth):
        print(' depth %2d: %s' % (d, dict(by_depth[d])))


NAMES = ['first order at the centre', 'first-order slopes', 'radius of the b_q', 'secant offsets',
         'second-order sum', 'parameter terms', 'b_q: |J0 centre| r(dot)', 'b_q: |dot centre| r(J0)',
         'b_q: dev x dev', 'b_q: slopes x slopes', 'b_q: radius x deviation', 'dot: |dbar centre| r(w)',
         'dot: |w centre| r(dbar)', 'dot: dev x dev', 'dot: S S y part', 'dot: S S y (plain)',
         'straddling b_q: |centre|', 'straddling b_q: slopes', 'straddling b_q: radius', 'straddling b_q: count',
         'J0 entries of the row straddling 0', 'J0 entries: radius / |centre|']


def bounds(path):
    columns = [[] for _ in NAMES]
    for line in open(path):
        if not line.startswith('BND'):
            continue
        for i, x in enumerate(map(float, line.split()[2:])):
            columns[i].append(x)
    print('%d full bounds' % len(columns[0]))
    for name, values in zip(NAMES, columns):
        if values:
            print('%-36s mean %.4f  q10/50/90 %.4f %.4f %.4f' % ((name,) + quantiles(values)))


if __name__ == '__main__':
    if len(sys.argv) != 3 or sys.argv[1] not in ('boxes', 'bounds'):
        sys.exit(__doc__)
    (boxes if sys.argv[1] == 'boxes' else bounds)(sys.argv[2])
