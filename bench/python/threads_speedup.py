#!/usr/bin/python3
"""Do Python threads putt in parallel as well as the library's own thread pool?

Times n ball putts on one thread against 2n on two Python threads (one SystemData each), and the
same work through System.sweep's C++ pool, interleaved, `--repeats` times; prints the medians as a
Markdown table. A speed figure, not a test: on a shared 2-core machine it moves with the load
(the GIL release itself is tested structurally in tests/python/test_module.py).

    PYTHONPATH=build/python /usr/bin/python3 bench/python/threads_speedup.py [--putts 12] [--check 1.25]

--check R exits 1 if the Python threads' ratio exceeds R x the pool's (or 1.7, whichever is larger).
"""
import argparse
import os
import statistics
import sys
import threading
import time

import minigolf


def python_threads(system, n, threads):
    def run():
        data = system.make_data()
        for k in range(n):
            system.putt(0.001 * k, 2.0, ball_only=True, data=data, record_interval=0.0)
    pool = [threading.Thread(target=run) for _ in range(threads)]
    start = time.perf_counter()
    for th in pool:
        th.start()
    for th in pool:
        th.join()
    return time.perf_counter() - start


def library_pool(system, n, threads):
    angles = [0.001 * k for k in range(n)]
    start = time.perf_counter()
    system.sweep(angles, [2.0] * threads, ball_only=True, threads=threads)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--putts", type=int, default=12, help="putts per thread (default 12)")
    parser.add_argument("--repeats", type=int, default=5, help="interleaved repeats (default 5)")
    parser.add_argument("--check", type=float, default=None, help="fail above R x the pool's ratio")
    args = parser.parse_args()
    if args.putts < 1 or args.repeats < 1:
        sys.exit("threads_speedup: --putts and --repeats must be at least 1")
    cores = len(os.sched_getaffinity(0))
    system = minigolf.System(field="flat")
    ours, pool = [], []
    for r in range(args.repeats):
        ours.append(python_threads(system, args.putts, 2) / python_threads(system, args.putts, 1))
        pool.append(library_pool(system, args.putts, 2) / library_pool(system, args.putts, 1))
        if sys.stderr.isatty():
            print(f"\rrepeat {r + 1}/{args.repeats}", end="", file=sys.stderr, flush=True)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    ours_median, pool_median = statistics.median(ours), statistics.median(pool)
    print(f"{cores} cores, load average {os.getloadavg()[0]:.1f}; time for 2 x {args.putts} putts "
          f"on 2 threads / time for {args.putts} on 1 (2.0: no parallelism, 1.0: perfect)\n")
    print("| threads | median | min | max |")
    print("|---|---|---|---|")
    for name, ratios, median in (("Python threads", ours, ours_median), ("C++ pool", pool, pool_median)):
        print(f"| {name} | {median:.2f} | {min(ratios):.2f} | {max(ratios):.2f} |")
    if args.check is not None and ours_median > max(1.7, args.check * pool_median):
        print(f"threads_speedup: Python threads {ours_median:.2f} x, above {args.check} x the pool's "
              f"{pool_median:.2f} x", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
