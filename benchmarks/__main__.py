"""``python -m benchmarks`` runs the suite; ``python -m benchmarks gateway`` the gateway's
scale benchmark (``benchmarks/gateway.py``)."""

import sys

if sys.argv[1:2] == ["gateway"]:
    from benchmarks.gateway import main as gateway_main

    sys.exit(gateway_main(sys.argv[2:]))

from benchmarks.run import main

sys.exit(main())
