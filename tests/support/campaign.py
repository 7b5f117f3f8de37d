"""The campaign tests' shared text and helpers: the test system and campaign files, writing a
campaign folder, running a campaign in-process or as a separate process."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

#: A system of the crasher (y = gain * t, misbehaving on request) and the ticker (a clock every 0.25 s).
SYSTEM = """\
[experiment]
stop = 2.0
step = 0.25

[instances.crasher]
fmu = "crasher.fmu"

[instances.ticker]
fmu = "ticker.fmu"
"""


#: The campaign of the execution tests: 6 runs, the 3 with crash_time = 1 segfault at t = 1 s.
CAMPAIGN = """\
title = "test campaign"
system = "system.toml"
keep = "results"
timeout = 30.0

[grid]
"crasher.gain" = [1.0, 2.0, 3.0]
"crasher.crash_time" = [-1.0, 1.0]

[metrics]
y = { final = "crasher.y" }
y_at_1 = { at = "crasher.y", time = 1.0 }
ticks = { ticks = "ticker.out" }
extra = "extra_metrics:halves"

[figure]
metric = "y"
x = "crasher.gain"
series = "crasher.crash_time"
"""
def slow_campaign(runs: int, delay: float) -> str:
    """``runs`` runs of 10 steps, each step ``delay`` seconds of wall time; y = gain over [0, 1] s
    with gain = 1, 2, ..., runs."""
    gains = ", ".join(f"{g:.1f}" for g in range(1, runs + 1))
    return (f'system = "system.toml"\nstop = 1.0\nstep = 0.1\n\n[grid]\n"crasher.gain" = [{gains}]\n'
            f'"crasher.delay" = [{delay}]\n\n[metrics]\ny = {{ final = "crasher.y" }}\n')


EXTRA_METRICS = """\
def halves(results):
    return {"half_y": results.column("crasher.y")[-1] / 2}
"""


def run_quietly(campaign: Path, out: Path, **options):
    from robogen.campaign import run_campaign

    return run_campaign(campaign, out, progress=False, echo=lambda line: None, **options)


def write_campaign_folder(folder: Path, fmus: dict[str, Path], text: str, system: str = SYSTEM, **files: str) -> Path:
    for name, path in fmus.items():
        target = folder / f"{name}.fmu"
        if not target.exists():
            target.write_bytes(path.read_bytes())
    (folder / "system.toml").write_text(system, encoding="utf-8")
    for name, content in files.items():
        (folder / name).write_text(content, encoding="utf-8")
    campaign = folder / "campaign.toml"
    campaign.write_text(text, encoding="utf-8")
    return campaign


class CampaignProcess:
    """``robogen campaign ARGS`` as a separate process in a session of its own, to be stopped or
    disturbed while it runs; everything left of that session is killed on exit."""

    def __init__(self, *args: str) -> None:
        self.process = subprocess.Popen([sys.executable, "-m", "robogen", "campaign", *args], stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True, start_new_session=True)

    def wait_for_journal(self, journal: Path, lines: int, timeout: float = 60) -> None:
        """Until ``journal`` holds ``lines`` finished runs."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and (not journal.exists() or len(journal.read_text().splitlines()) < lines):
            time.sleep(0.02)

    def finish(self, timeout: float = 120) -> tuple[int, str]:
        """(exit status, standard error) once the campaign has ended."""
        _, err = self.process.communicate(timeout=timeout)
        return self.process.returncode, err

    def __enter__(self) -> "CampaignProcess":
        return self

    def __exit__(self, *exc) -> None:
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait(timeout=30)
