"""ASAM OpenSCENARIO XML 1.x (+ OpenDRIVE) both ways: a case's run out, a file in as a case.

- `export`: `export_case` / `export_run` write ``<case>.xosc`` and its road ``<case>.xodr``
  (`opendrive`), with ``scenariogeneration``;
- `import_`: `read_xosc` reads a file of the supported subset (`subset`) into a `Case` whose
  recorded motion highway-env drives: `document` (parameters, checked reads), `road` (the
  OpenDRIVE roads), `storyboard` (Init, events, conditions, actions) and `player` (plays them
  into timed trajectories).
"""
