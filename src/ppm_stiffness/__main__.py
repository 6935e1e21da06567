"""``python -m ppm_stiffness`` runs the CLI."""

import sys

from ppm_stiffness.cli import main

sys.exit(main())
