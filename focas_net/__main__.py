"""``python -m focas_net`` runs the command line."""

import sys

from focas_net.cli import main

sys.exit(main())
