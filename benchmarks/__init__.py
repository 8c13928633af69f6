"""The focas_net benchmark suite: focas_net against a plain-asyncio floor and pymodbus.

Run ``python -m benchmarks`` (``--quick`` for a smoke run, ``--help`` for the options).
"""
