"""The launch worker: `python -m pkgforge.launch.worker`, one JSON request per line on stdin.

Launch files are user code: they run only here, in a subprocess the parent
kills when one runs past its time limit. Replies go to a private copy of the
original stdout; the launch files' own prints (and their children's) go to
/dev/null, so nothing they write can corrupt the replies.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

API = Path(__file__).resolve().parent / "api"


def _install_api() -> None:
    """Put pkgforge's launch, launch_ros, launch_xml and launch_yaml first on the path."""
    sys.path.insert(0, str(API))
    try:
        import ament_index_python.packages  # noqa: F401  (the real one, from the ament extra or ROS)
    except ImportError:
        sys.path.insert(0, str(API.parent / "api_ament"))


def main() -> None:
    replies = os.fdopen(os.dup(1), "w", buffering=1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    sys.stdout = sys.stderr = open(os.devnull, "w")
    _install_api()
    from pkgforge.launch.evaluate import evaluate
    from pkgforge.robot import process_model

    for line in sys.stdin:
        request = json.loads(line)
        try:
            if "model" in request:
                result = process_model(request["model"], request.get("mappings", {}))
            else:
                result = evaluate(request["file"], request.get("arguments", {}))
        except BaseException as error:  # noqa: BLE001 - the reply must always come
            result = {"status": "load-error", "error": {"stage": "worker", "type": type(error).__name__,
                                                        "message": str(error),
                                                        "file": request.get("file") or request.get("model"),
                                                        "line": None}}
        result["request"] = request
        replies.write(json.dumps(result, default=str) + "\n")


if __name__ == "__main__":
    main()
