"""``python3 -m dem.wall CASE.yaml -o OUT.nc``."""

from dem.entry import exit_now
from dem.wall.cli import main

# everything is written and closed by now: end without the interpreter's teardown, so that
# SIGINT/SIGTERM end the process at once
exit_now(main())
