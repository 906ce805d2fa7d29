"""Front end: read a mission (and its includes), validate it, build the model.

    read (xmlsource) -> structural XSD (schema/btcpp_v4.xsd) -> semantic checks
    -> model (model.py) -> mission XSD (xsd.py) as a final backstop

Every problem becomes a diagnostic at `path:line:col`; all problems of a
mission are reported together.

The package, by stage: `sources` (the mission, includes, tree libraries, load_mission),
`models` (models files, TreeNodesModel), `checks` (trees, nodes, whole-mission checks),
`base` (the state and helpers they share).
"""

from btgen.frontend.loader.base import (
    _PORT_NAME_RE,
    MAX_INCLUDE_DEPTH,
    MAX_NODES,
    RESERVED_MODEL_IDS,
    is_remap,
    remap_key,
)
from btgen.frontend.loader.models import merged_model, model_conflict
from btgen.frontend.loader.sources import files_read, load_mission

__all__ = [
    "MAX_INCLUDE_DEPTH",
    "MAX_NODES",
    "RESERVED_MODEL_IDS",
    "_PORT_NAME_RE",
    "files_read",
    "is_remap",
    "load_mission",
    "merged_model",
    "model_conflict",
    "remap_key",
]
