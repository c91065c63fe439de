import sys

from femslide.app.cli import main

sys.exit(main())
