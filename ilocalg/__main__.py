import sys

from ilocalg.cli import main

sys.exit(main())
