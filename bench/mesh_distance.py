"""Vertex distance between two OFF meshes with the same vertex order.

    python3 bench/mesh_distance.py A.off B.off

Prints the largest and the RMS vertex distance divided by A's bounding-box
diagonal. Standard library only (bench/tolerance_sweep.sh uses it)."""
import math
import sys


def load_off(path):
    with open(path) as f:
        lines = [l for l in f if l.strip() and not l.lstrip().startswith("#")]
    if not lines or not lines[0].split()[0].endswith("OFF"):
        sys.exit("%s: not an OFF file" % path)
    header = lines[0].split()[1:] or lines[1].split()
    first = 1 if lines[0].split()[1:] else 2
    n = int(header[0])
    return [tuple(float(x) for x in l.split()[:3]) for l in lines[first:first + n]]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: mesh_distance.py A.off B.off")
    a, b = load_off(sys.argv[1]), load_off(sys.argv[2])
    if len(a) != len(b):
        sys.exit("%s and %s: %d and %d vertices" % (sys.argv[1], sys.argv[2], len(a), len(b)))
    lo = [min(p[i] for p in a) for i in range(3)]
    hi = [max(p[i] for p in a) for i in range(3)]
    diag = math.dist(lo, hi)
    if diag == 0.0:
        sys.exit("%s: all vertices coincide (no bounding-box diagonal)" % sys.argv[1])
    d = [math.dist(p, q) for p, q in zip(a, b)]
    print("max %.2e rms %.2e" % (max(d) / diag, math.sqrt(sum(x * x for x in d) / len(d)) / diag))


main()
