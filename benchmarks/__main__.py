"""`python -m benchmarks [NAME ...]`: run every benchmark module (or the named ones) and print
its figures. Times are medians over repeated runs; ratios are against floors measured in the
same run, never absolute assertions. The process runs as `radar-harness` and the sweep workers
do (`harness.runtime.prepare_process`: one BLAS thread, the allocator tuning); bench_pipeline
also reports the chain under glibc's default allocator, measured in a fresh interpreter.
`python -m benchmarks floors` prints the README's performance table; `python -m benchmarks
equivalence` measures the statistics a bit-moving speed change must keep (its own options)."""
from __future__ import annotations

import importlib
import pkgutil
import sys

import benchmarks
from benchmarks import equivalence


def main(argv: list[str]) -> int:
    from harness.runtime import prepare_process
    prepare_process()
    if argv[:1] == ["equivalence"]:  # a tool with its own options, not a timing bench
        return equivalence.main(argv[1:])
    names = sorted(m.name for m in pkgutil.iter_modules(benchmarks.__path__)
                   if m.name.startswith("bench_"))
    if argv:
        names = [n for n in names if any(a in n for a in argv)]
    for name in names:
        print(f"== {name}", flush=True)
        for line in importlib.import_module(f"benchmarks.{name}").run():
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
