"""The project's error types: what is the user's fault and what is ours.

`BadInput` is raised by every validation (configs, files, CLI arguments, registered records):
the command line turns it into exit code 2 and one line naming the field, the value and the
limit. Anything else that escapes a command is a bug in this code or a library and keeps its
traceback (exit 1). `BadInput` subclasses `ValueError`, so code that catches ``ValueError``
around a validation keeps working.

Examples
--------
>>> from core.errors import BadInput
>>> issubclass(BadInput, ValueError)
True
"""
from __future__ import annotations

__all__ = ["BadInput", "BadInputFile", "OutputError"]


class BadInput(ValueError):
    """Input the harness cannot run: a config value, a file, a key or an argument.

    The message names the field (or file and key), the value and the limit.
    """


class BadInputFile(BadInput):
    """An input path that is not a readable regular file of bounded size."""


class OutputError(BadInput):
    """An output that could not be written (full disk, read-only folder, ...): not a bug, the
    system refused; the message names the path and the system's reason."""
