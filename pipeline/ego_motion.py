"""Deprecated alias of `pipeline.tracking.ego_motion` (moved into the tracker package).

Kept so branches written against the old module keep importing while they land; import from
`pipeline.tracking.ego_motion` instead. Delete this file once nothing imports it.
"""
import warnings

from .tracking.ego_motion import *  # noqa: F401,F403
from .tracking.ego_motion import __all__  # noqa: F401

warnings.warn("pipeline.ego_motion is deprecated: import pipeline.tracking.ego_motion",
              DeprecationWarning, stacklevel=2)
