"""``python -m gather_verify`` runs the command line."""

import sys

from gather_verify.cli import main

sys.exit(main())
