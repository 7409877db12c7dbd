"""The orchestration layer: the only package that wires scenarios -> radarsim -> pipeline ->
metrics together.

- `harness.cli`: the `radar-harness` command line (one `cmd_*` module per command);
- `harness.sweep`: sweep files, scheduling on a process pool or Dask, resumable cells, tables;
- `harness.cell`: one cell (scenario x variant x seed) and its frame loop;
- `harness.report`: the HTML report and its registry of sections;
- `harness.gates`: CI gates and verdicts;
- `harness.runtime`: process set-up (one BLAS thread, stop signals, stoppable pools);
- `harness.sweeps/`: the shipped sweep files (default, CI, schemes, interference, mitigation,
  shifter).
"""
