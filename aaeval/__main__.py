import sys

from aaeval.cli import main

sys.exit(main())
