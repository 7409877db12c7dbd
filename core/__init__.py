"""The domain-free foundation every package of the harness may import; it imports none of them.

- `core.registry`: the one `Registry` class behind every registry (schemes, chips, boards, CFAR
  modes, repair methods, road layouts, cases, metrics, ...);
- `core.checks`: the shared field checks of every config (`require`, `one_of`) and the one TOML
  policy (`read_toml`, `check_keys`, `build_from_table`);
- `core.fileio`: safe input (regular files of bounded size) and atomic output;
- `core.errors`: `BadInput` (bad input: exit 2, one line) and its kinds; anything else is a bug.

Layer order, bottom up: core < scenarios < radarsim < pipeline < metrics < harness.
"""
