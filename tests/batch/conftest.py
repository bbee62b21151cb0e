"""Batch tests: any Ray cluster they start listens on loopback only.

``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0`` makes Ray take 127.0.0.1 as the node address; Ray
reads it when it is first imported, so it is set here, before any test imports Ray, and is
inherited by every Ray process the tests start.
"""

import os

os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"
# no usage statistics sent from test clusters
os.environ["RAY_USAGE_STATS_ENABLED"] = "0"
