from navlab.cli import main

raise SystemExit(main())
