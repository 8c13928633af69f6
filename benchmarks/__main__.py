"""``python -m benchmarks`` runs the suite."""

import sys

from benchmarks.run import main

sys.exit(main())
