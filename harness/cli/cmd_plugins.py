"""`radar-harness plugins [--plugin MODULE_OR_FILE ...] [--registry NAME]`.

Loads the installed plugins (entry points ``radar_harness.plugins``) and the ``--plugin`` ones,
prints every loaded plugin (module, how it was given, distribution and version, source hash)
and every registry's entries with their origin: "built in", ``plugin <module> (<distribution>
<version>)``, or the module that registered it. A plugin that fails to import is named with
its error and the command exits 2 (`harness.plugins`).
"""
from __future__ import annotations

import argparse

from harness.cli.args import add_plugin_option


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_plugin_option(parser)
    parser.add_argument("--registry", default=None,
                        help="list only this registry (e.g. scheme, chain, 'CFAR mode', board)")


def run(args: argparse.Namespace) -> int:
    import pandas as pd

    from core.errors import BadInput
    from harness import plugins
    plugins.import_builtins()  # the listing shows every built-in registry too
    loaded = plugins.loaded_plugins()
    print(f"plugins ({len(loaded)}):" if loaded else "plugins: none loaded (entry point group "
          f"{plugins.ENTRY_POINT_GROUP!r}, --plugin)")
    for p in loaded:
        where = f"{p.distribution} {p.version}" if p.distribution else p.path or "-"
        print(f"  {p.module:32s} {p.how:12s} {where}  source {p.sha256}")
    rows = pd.DataFrame(plugins.registry_entries())
    if args.registry is not None:
        known = sorted(set(rows["registry"]))
        if args.registry not in known:
            raise BadInput(f"--registry {args.registry!r} is not one of {known}")
        rows = rows[rows["registry"] == args.registry]
    with pd.option_context("display.max_rows", None, "display.width", 200,
                           "display.max_colwidth", 70):
        print(rows[["registry", "name", "origin"]].to_string(index=False))
    return 0
