from btgen.cli import main

raise SystemExit(main())
