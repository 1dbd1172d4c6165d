from dem.wall.cli import main

raise SystemExit(main())
