"""Results of a run: rows of samples, pair-by-pair ratios, the targets, the table and the JSON.

Pure functions and dataclasses only, so the arithmetic is testable without running anything.
"""

from __future__ import annotations

import json
import math
import statistics
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

FLOOR = "floor"
FOCAS = "focas_net"
PEER = "pymodbus"
THROUGHPUT_MODES = ("seq", "pipe64", "conc100")
#: The least median ratio to the floor of each throughput mode.
THROUGHPUT_TARGETS = (1.0, 0.9, 0.9)
#: pmc4k (4 KiB in 32-byte chunks): the least speed relative to the floor's pipelined frames.
PMC4K_TARGET = 0.8
MEMORY_TARGET_KIB = 4.0


@dataclass(frozen=True, slots=True)
class Summary:
    median: float
    min: float
    max: float

    @classmethod
    def of(cls, samples: Sequence[float]) -> Summary:
        if not samples:
            raise ValueError("no samples")
        return cls(statistics.median(samples), min(samples), max(samples))


def pairwise_ratios(numerators: Sequence[float], denominators: Sequence[float]) -> list[float]:
    """``numerators[i] / denominators[i]`` for each repetition ``i`` of the same run."""
    if len(numerators) != len(denominators):
        raise ValueError(f"{len(numerators)} samples against {len(denominators)}: not pairs")
    return [n / d if d else math.inf for n, d in zip(numerators, denominators, strict=True)]


@dataclass(slots=True)
class Row:
    """One line of the table: a measure of one subject in one scenario."""

    scenario: str
    subject: str
    unit: str
    samples: list[float]
    ratio_to: str | None = None
    ratios: list[float] | None = None
    note: str = ""
    #: Counts that are not samples (e.g. bits lost over every repetition).
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def summary(self) -> Summary:
        return Summary.of(self.samples)

    @property
    def ratio(self) -> Summary | None:
        return Summary.of(self.ratios) if self.ratios else None

    def to_json(self) -> dict[str, Any]:
        data = asdict(self)
        data["summary"] = asdict(self.summary)
        ratio = self.ratio
        data["ratio"] = asdict(ratio) if ratio is not None else None
        return data


@dataclass(frozen=True, slots=True)
class Check:
    """One target: ``passed`` is None when it could not be measured (and ``detail`` says why)."""

    name: str
    passed: bool | None
    detail: str

    @property
    def verdict(self) -> str:
        return "SKIP" if self.passed is None else ("PASS" if self.passed else "FAIL")


@dataclass(slots=True)
class Results:
    machine: dict[str, str]
    command: str
    config: dict[str, Any]
    rows: list[Row] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)

    def find(self, scenario: str, subject: str) -> Row | None:
        for row in self.rows:
            if row.scenario == scenario and row.subject == subject:
                return row
        return None

    def to_json(self) -> dict[str, Any]:
        return {
            "machine": self.machine,
            "command": self.command,
            "config": self.config,
            "rows": [row.to_json() for row in self.rows],
            "skipped": self.skipped,
            "checks": [{**asdict(c), "verdict": c.verdict} for c in self.checks],
        }


def _ratio_check(name: str, row: Row | None, low: float | None, high: float | None) -> Check:
    if row is None or row.ratio is None:
        return Check(name, None, "not measured")
    value = row.ratio.median
    ok = (low is None or value >= low) and (high is None or value <= high)
    return Check(name, ok, f"median ratio {value:.2f}")


def evaluate(results: Results, *, fleet_size: int, fleet_hz: float) -> list[Check]:
    """The targets of the suite, each PASS, FAIL or SKIP."""
    checks: list[Check] = []
    for mode, low in zip(THROUGHPUT_MODES, THROUGHPUT_TARGETS, strict=True):
        checks.append(
            _ratio_check(f"{mode} >= {low} x floor", results.find(mode, FOCAS), low, None)
        )
    checks.append(
        _ratio_check(
            f"pmc4k >= {PMC4K_TARGET} x the floor's speed on as many frames",
            results.find("pmc4k", FOCAS),
            PMC4K_TARGET,
            None,
        )
    )
    storm = results.find("bitstorm", FOCAS)
    if storm is None:
        checks.append(Check("bitstorm: zero lost", None, "not measured"))
    else:
        lost, errors = storm.extra.get("lost", -1), storm.extra.get("errors", -1)
        checks.append(
            Check(
                "bitstorm: zero lost",
                lost == 0 and errors == 0,
                f"{lost:g} bits lost, {errors:g} failed in {storm.extra.get('calls', 0):g} calls",
            )
        )
    memory = results.find("memory", FOCAS)
    name = f"memory <= {MEMORY_TARGET_KIB:g} KiB per idle connection"
    if memory is None:
        checks.append(Check(name, None, "not measured"))
    else:
        kib = memory.summary.median
        checks.append(Check(name, kib <= MEMORY_TARGET_KIB, f"{kib:.1f} KiB"))
    rate = results.find("fleet_rate", FOCAS)
    cpu = results.find("fleet_cpu", FOCAS)
    name = f"fleet: {fleet_size} machines at {fleet_hz:g} Hz, client CPU < 0.5 core"
    if rate is None or rate.ratio is None or cpu is None:
        checks.append(Check(name, None, "not measured"))
    else:
        achieved = rate.ratio.median
        cores = cpu.summary.median
        checks.append(
            Check(
                name,
                achieved >= 0.99 and cores < 0.5,
                f"{achieved:.1%} of the nominal rate, {cores:.2f} core",
            )
        )
    for mode in THROUGHPUT_MODES:
        name = f"{mode}: ahead of pymodbus"
        ours, peer = results.find(mode, FOCAS), results.find(mode, PEER)
        if ours is None or peer is None:
            checks.append(Check(name, None, "not measured"))
            continue
        ratios = pairwise_ratios(ours.samples, peer.samples)
        value = statistics.median(ratios)
        checks.append(Check(name, value > 1.0, f"{value:.2f} x pymodbus"))
    return checks


def _fmt(value: float) -> str:
    if math.isinf(value):
        return "inf"
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    if abs(value) >= 10:
        return f"{value:.1f}"
    return f"{value:.3f}"


def render_table(rows: Iterable[Row]) -> str:
    """The table of rows as fixed-width text."""
    header = ("scenario", "subject", "median", "min", "max", "unit", "ratio (med [min..max])", "vs")
    lines: list[tuple[str, ...]] = [header]
    for row in rows:
        s = row.summary
        r = row.ratio
        ratio = f"{r.median:.2f} [{r.min:.2f}..{r.max:.2f}]" if r is not None else ""
        lines.append(
            (
                row.scenario,
                row.subject,
                _fmt(s.median),
                _fmt(s.min),
                _fmt(s.max),
                row.unit,
                ratio,
                (row.ratio_to or "") + (f"  ({row.note})" if row.note else ""),
            )
        )
    widths = [max(len(line[i]) for line in lines) for i in range(len(header))]
    out = []
    for n, line in enumerate(lines):
        cells = [
            cell.rjust(widths[i]) if 2 <= i <= 4 else cell.ljust(widths[i])
            for i, cell in enumerate(line)
        ]
        out.append("  ".join(cells).rstrip())
        if n == 0:
            out.append("  ".join("-" * w for w in widths))
    return "\n".join(out)


def render_checks(checks: Iterable[Check]) -> str:
    return "\n".join(f"{c.verdict:4}  {c.name}: {c.detail}" for c in checks)


def print_results(results: Results, header: Sequence[str], json_path: Path, strict: bool) -> int:
    """Print ``header``'s lines, the table, the checks and the notes of ``results``, write
    them as JSON to ``json_path``; the exit status: 1 when ``strict`` and a check failed."""
    for line in header:
        print(line)
    print()
    print(render_table(results.rows))
    print()
    print(render_checks(results.checks))
    for message in results.skipped:
        print(f"note: {message}")
    json_path.parent.mkdir(parents=True, exist_ok=True)
    json_path.write_text(json.dumps(results.to_json(), indent=2) + "\n", encoding="utf-8")
    print(f"results written to {json_path}")
    failed = any(c.passed is False for c in results.checks)
    return 1 if strict and failed else 0
