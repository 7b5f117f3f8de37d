import sys

from robogen.cli import main

sys.exit(main())
