"""Where a ROS package is, for `<include ros_pkg="PKG" path="FILE"/>`.

BehaviorTree.CPP built with ROS 2 support opens `<share directory of PKG>/FILE` (ament's
`get_package_share_directory`); built without ROS, it refuses the include (both 4.6.2 and 4.10.0,
recorded on the oracle: "Using attribute [ros_pkg] in <include>, but this library was compiled
without ROS support"). btgen looks the package up, in order, in the table the user gives (`btgen
check`'s `ros-packages` of [tool.btgen]: package -> its share folder), in `AMENT_PREFIX_PATH`
(`<prefix>/share/<PKG>`, as ament does) and in `ROS_PACKAGE_PATH` (a folder named PKG, or holding
one, under each entry, as ROS 1's rospack finds source packages); not found, the include is an
error that says where it looked.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Optional


def find(
    package: str, table: Optional[Mapping[str, str]] = None, environ: Optional[Mapping[str, str]] = None
) -> Optional[str]:
    """The folder of `package`, or None."""
    env = os.environ if environ is None else environ
    given = dict(table or {})
    if package in given:
        return given[package] if os.path.isdir(given[package]) else None
    if not package or "/" in package or package in (".", ".."):
        return None
    for prefix in (env.get("AMENT_PREFIX_PATH") or "").split(os.pathsep):
        if prefix and os.path.isdir(os.path.join(prefix, "share", package)):
            return os.path.join(prefix, "share", package)
    for root in (env.get("ROS_PACKAGE_PATH") or "").split(os.pathsep):
        if not root:
            continue
        if os.path.basename(os.path.normpath(root)) == package and os.path.isdir(root):
            return root
        if os.path.isdir(os.path.join(root, package)):
            return os.path.join(root, package)
    return None


def not_found(package: str, table: Optional[Mapping[str, str]] = None) -> str:
    where = "AMENT_PREFIX_PATH (share/<package>), ROS_PACKAGE_PATH"
    given = dict(table or {})
    if package in given:
        return f"<include ros_pkg=...>: the folder `{given[package]}` given for package `{package}` does not exist"
    return (
        f"<include ros_pkg=...>: package `{package}` not found (looked in {where} and `ros-packages` of "
        f"[tool.btgen]); BehaviorTree.CPP built without ROS refuses such an include, so give its folder "
        f"there or a path relative to this file"
    )
