"""Deprecated alias of `pipeline.tracking` (the group tracker is a package now).

Kept so branches written against the old module keep importing while they land; import from
`pipeline.tracking` instead. Delete this file once nothing imports it.
"""
import warnings

from .tracking import *  # noqa: F401,F403
from .tracking import __all__  # noqa: F401

warnings.warn("pipeline.tracker is deprecated: import pipeline.tracking", DeprecationWarning,
              stacklevel=2)
