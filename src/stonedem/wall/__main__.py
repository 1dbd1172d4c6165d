"""``python3 -m stonedem.wall CASE.yaml -o OUT.nc``."""

from stonedem.entry import exit_now
from stonedem.wall.cli import main

# everything is written and closed by now: end without the interpreter's teardown, so that
# SIGINT/SIGTERM end the process at once
exit_now(main())
