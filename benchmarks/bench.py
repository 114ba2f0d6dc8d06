"""The compiled engine against Pinocchio: ``python benchmarks/bench.py [ROBOT] [--output FILE]``.

The same as ``featherdyn bench``; the code lives in :mod:`featherdyn.tools.bench`
so that the installed command can run it. Prints ratios against Pinocchio
measured in this process (interleaved repetitions, medians), with versions and
machine, batched throughput, and a scaling table over chains of 8…512 links.
"""

from __future__ import annotations

import sys

from featherdyn.tools.bench import bench_main

if __name__ == "__main__":
    sys.exit(bench_main(sys.argv[1:]))
