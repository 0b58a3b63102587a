"""The launch worker's entry: `python -m pkgforge.evaluation [--fork-server FD]`.

With --fork-server it is the fork server (sandbox/zygote.py) that forks each worker after the
evaluator's imports; without, one worker (its coordinator, sandbox/coordinator.py) on stdin and
stdout. Either way the requests mean what evaluation/requests.py says.
"""

import os
import sys

from pkgforge.evaluation.requests import RequestEvaluator

if sys.argv[1:2] == ["--fork-server"]:
    from pkgforge.sandbox.zygote import serve

    serve(int(sys.argv[2]), RequestEvaluator())
    # nothing to flush or remove, and the interpreter's own exit with lxml, xacro and the
    # evaluator loaded takes ~60 ms that pkgforge would wait for (Zygote.close)
    os._exit(0)
else:
    from pkgforge.sandbox.coordinator import main

    main(RequestEvaluator())
    sys.exit(0)
