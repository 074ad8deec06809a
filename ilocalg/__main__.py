import sys

from ilocalg.workflow.cli import main

sys.exit(main())
