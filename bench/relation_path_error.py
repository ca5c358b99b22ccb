#!/usr/bin/env python3
"""How far a path of k ground-truth relations drifts from a reference trajectory: the error
of the relations' own judge of loop links (lrgc_apps/eval/relation_truth.h), by path length.

    bench/relation_path_error.py R.relations REFERENCE.tum [--sources N] [--seed S]

For N relation timestamps drawn at random (150), every timestamp within 16 relations by a
path of fewest relations (breadth first, as CRelationTruth::reach) and at least 60 s apart
(a revisit, as the judge sees them) is composed along that path and compared with the
reference's relative pose (e.g. the dense run's trajectory.tum for a sparse log's relations).
Prints, per path length k, the median and 90th percentile of the position difference [m]
and the share of pairs more than 0.3 m apart (TLoopRecallParams::maxXY_m).
"""
import argparse
import collections
import math
import random


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], wrap(a[2] + b[2]))


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def between(a, b):
    return compose(inverse(a), b)


def load_tum(path):
    poses = {}
    with open(path) as f:
        for line in f:
            v = line.split()
            if not v or v[0].startswith('#'):
                continue
            phi = 2 * math.atan2(float(v[6]), float(v[7])) if len(v) >= 8 else float(v[3])
            poses[round(float(v[0]), 4)] = (float(v[1]), float(v[2]), phi)
    return poses


def load_relations(path):
    edges = collections.defaultdict(list)
    with open(path) as f:
        for line in f:
            v = line.split()
            if len(v) < 8:
                continue
            a, b = round(float(v[0]), 4), round(float(v[1]), 4)
            m = (float(v[2]), float(v[3]), float(v[7]))
            edges[a].append((b, m))
            edges[b].append((a, inverse(m)))
    return edges


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('relations')
    ap.add_argument('reference')
    ap.add_argument('--sources', type=int, default=150)
    ap.add_argument('--seed', type=int, default=1)
    args = ap.parse_args()
    ref = load_tum(args.reference)
    edges = load_relations(args.relations)
    nodes = sorted(n for n in edges if n in ref)
    random.seed(args.seed)
    by_length = collections.defaultdict(list)
    for src in random.sample(nodes, min(args.sources, len(nodes))):
        reached = {src: ((0.0, 0.0, 0.0), 0)}
        queue = collections.deque([src])
        while queue:
            n = queue.popleft()
            pose, k = reached[n]
            if k >= 16:
                continue
            for m, motion in edges[n]:
                if m not in reached:
                    reached[m] = (compose(pose, motion), k + 1)
                    queue.append(m)
        for m, (pose, k) in reached.items():
            if m not in ref or abs(m - src) < 60:
                continue
            d = between(ref[src], ref[m])
            by_length[k].append(math.hypot(d[0] - pose[0], d[1] - pose[1]))
    print('relations  pairs  median [m]  p90 [m]  share > 0.3 m')
    for k in sorted(by_length):
        v = sorted(by_length[k])
        n = len(v)
        print('%9d  %5d  %10.3f  %7.3f  %13.3f' %
              (k, n, v[n // 2], v[int(0.9 * n)], sum(x > 0.3 for x in v) / n))


if __name__ == '__main__':
    main()
