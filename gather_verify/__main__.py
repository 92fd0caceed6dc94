"""``python -m gather_verify`` runs the command line."""

import sys

from gather_verify.cli import main

if __name__ == "__main__":
    sys.exit(main())
