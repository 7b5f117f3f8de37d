"""Python FMUs are extracted and loaded once per process and reused by every later run
(robogen.cosim.shared); each run still instantiates them afresh."""

from __future__ import annotations

import shutil
import zipfile
from pathlib import Path

from robogen.cosim import simulate_system
from robogen.cosim.shared import SHARED

SYSTEM = """[experiment]
stop = 1.0
step = 0.25
[instances.p]
fmu = "MISBEHAVING"
"""


def mapped_copies(name: str) -> set[str]:
    """The files named ``name`` this process has mapped (each dlopen of another path maps one)."""
    with open("/proc/self/maps", encoding="utf-8") as maps:
        return {line.split(None, 5)[5].strip().removesuffix(" (deleted)") for line in maps
                if line.rstrip().removesuffix(" (deleted)").endswith("/" + name)}


def test_later_runs_reuse_the_extracted_and_loaded_python_fmu_with_fresh_instances(tmp_path, misbehaving):
    system = tmp_path / "system.toml"
    system.write_text(SYSTEM.replace("MISBEHAVING", str(misbehaving)))
    first = simulate_system(system)
    before = mapped_copies("misbehaving.so")
    later = [simulate_system(system) for _ in range(3)]
    assert mapped_copies("misbehaving.so") == before  # no run mapped another copy of the binary
    assert len(before) >= 1
    # y follows time from a fresh instance in every run: 0 at the start, t + h after each step
    expected = [[0.0, 0, 0.0], [0.25, 0, 0.25], [0.5, 0, 0.5], [0.75, 0, 0.75], [1.0, 0, 1.0]]
    assert first.columns == ["time", "superdense", "p.y"]
    assert first.rows == expected
    assert all(r.rows == expected for r in later)
    folder, md = SHARED.load(misbehaving)
    assert SHARED.load(misbehaving) == (folder, md)  # the same extraction, not a new one
    assert SHARED.holds(folder) and (folder / "resources" / "pyfmu.json").is_file()
    assert md.co_simulation.model_identifier == "misbehaving"


def test_the_same_content_elsewhere_shares_the_folder_and_another_content_gets_its_own(tmp_path, misbehaving):
    copy = tmp_path / "copy.fmu"
    shutil.copyfile(misbehaving, copy)
    assert SHARED.load(copy) == SHARED.load(misbehaving)
    changed = tmp_path / "changed.fmu"
    shutil.copyfile(misbehaving, changed)
    with zipfile.ZipFile(changed, "a") as archive:
        archive.writestr("documentation/notes.txt", "another archive, the same model")
    assert SHARED.load(changed)[0] != SHARED.load(misbehaving)[0]


def test_a_folder_removed_from_under_the_registry_is_extracted_again(tmp_path, misbehaving):
    # a campaign's run process makes its run folder the temporary folder and removes it afterwards
    folder, _md = SHARED.load(misbehaving)
    shutil.rmtree(folder)
    system = tmp_path / "system.toml"
    system.write_text(SYSTEM.replace("MISBEHAVING", str(misbehaving)))
    assert simulate_system(system).rows[-1] == [1.0, 0, 1.0]
    again, _md = SHARED.load(misbehaving)
    assert (again / "resources" / "pyfmu.json").is_file()


def test_c_fmus_are_still_extracted_per_run(fmus):
    assert SHARED.load(Path(fmus["ticker"])) is None


def test_an_archive_rewritten_in_place_is_read_again(tmp_path, misbehaving):
    # the registry hashes an archive again only when its file changed: the same path with another
    # content (another size) is another FMU, and a C FMU written over a Python one is no Python FMU
    fmu = tmp_path / "rewritten.fmu"
    shutil.copyfile(misbehaving, fmu)
    first = SHARED.load(fmu)
    assert first == SHARED.load(misbehaving)
    with zipfile.ZipFile(fmu, "a") as archive:
        archive.writestr("documentation/notes.txt", "rewritten where it was")
    assert SHARED.load(fmu)[0] != first[0]
    with zipfile.ZipFile(fmu, "w") as archive:  # no resources/pyfmu.json any more
        archive.writestr("modelDescription.xml", "<fmiModelDescription/>")
    assert SHARED.load(fmu) is None
