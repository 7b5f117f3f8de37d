"""Safe extraction of untrusted archives: nothing is written outside the extraction folder."""

from __future__ import annotations

import os
import stat
import zipfile

import pytest

from robogen.cli import main
from robogen.diagnostics import RobogenError
from robogen.fmu.extract import Limits, extract_fmu, needed_to_run


def make_zip(path, members):
    """members: (name, data, unix mode or None)"""
    with zipfile.ZipFile(path, "w") as z:
        for name, data, mode in members:
            info = zipfile.ZipInfo(name)
            if mode is not None:
                info.create_system = 3
                info.external_attr = mode << 16
            z.writestr(info, data)
    return path


MD = b'<?xml version="1.0"?><fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="t"/>'


@pytest.mark.parametrize("name, mode, why", [
    ("../evil.txt", None, "member path contains '..'"),
    ("a/../../evil.txt", None, "member path contains '..'"),
    ("/tmp/evil.txt", None, "member has an absolute path"),
    ("C:/evil.txt", None, "member has an absolute path"),
    ("a\\..\\evil.txt", None, "member name contains a backslash"),
    ("link", stat.S_IFLNK | 0o777, "member is a symbolic link"),
    ("dev", stat.S_IFCHR | 0o644, "member is a device file, FIFO or socket"),
    ("fifo", stat.S_IFIFO | 0o644, "member is a device file, FIFO or socket"),
])
def test_malicious_members_are_rejected_before_anything_is_written(tmp_path, name, mode, why):
    fmu = make_zip(tmp_path / "bad.fmu", [("modelDescription.xml", MD, None), (name, b"/etc/passwd", mode)])
    dest = tmp_path / "out" / "x"
    with pytest.raises(RobogenError) as exc:
        extract_fmu(fmu, dest)
    assert exc.value.diagnostics[0].message == f"unsafe archive member '{name}': {why}"
    assert not (tmp_path / "out").exists()  # checked first: nothing written at all
    assert sorted(os.listdir(tmp_path)) == ["bad.fmu"]


def test_oversized_and_too_many_members(tmp_path):
    fmu = make_zip(tmp_path / "big.fmu", [("modelDescription.xml", MD, None), ("resources/big", b"\0" * 5000, None)])
    with pytest.raises(RobogenError) as exc:
        extract_fmu(fmu, tmp_path / "o1", Limits(max_bytes=4096))
    assert "unpacks to" in exc.value.diagnostics[0].message and "limit of 4096" in exc.value.diagnostics[0].message
    with pytest.raises(RobogenError) as exc:
        extract_fmu(fmu, tmp_path / "o2", Limits(max_members=1))
    assert exc.value.diagnostics[0].message == "archive has 2 members, more than the limit of 1"


def test_lying_size_header_is_caught_while_writing(tmp_path):
    fmu = make_zip(tmp_path / "liar.fmu", [("resources/big", b"\0" * 10000, None)])
    data = bytearray(fmu.read_bytes())
    # patch the central directory's uncompressed size (offset 24 in the entry) to claim 10 bytes
    cd = data.rfind(b"PK\x01\x02")
    data[cd + 24:cd + 28] = (10).to_bytes(4, "little")
    fmu.write_bytes(bytes(data))
    with pytest.raises((RobogenError, zipfile.BadZipFile)):
        extract_fmu(fmu, tmp_path / "o", Limits(max_bytes=100))


def test_a_good_archive_extracts(tmp_path, built):
    dest = extract_fmu(built["ticker"], tmp_path / "x")
    assert (dest / "modelDescription.xml").is_file() and (dest / "binaries" / "x86_64-linux" / "ticker.so").is_file()


def test_entity_expansion_is_refused(tmp_path):
    from robogen.fmu.modeldesc import read_model_description

    bomb = b'<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;">]><fmiModelDescription fmiVersion="3.0">&b;</fmiModelDescription>'
    with pytest.raises(RobogenError) as exc:
        read_model_description(bomb, "m.xml")
    assert "DOCTYPE or entities" in exc.value.diagnostics[0].message


def test_simulate_and_validate_reject_a_zip_slip_fmu(tmp_path, capsys):
    fmu = make_zip(tmp_path / "slip.fmu", [("modelDescription.xml", MD, None), ("../../slip.txt", b"x", None)])
    (tmp_path / "s.toml").write_text('[experiment]\nstop = 1\nstep = 0.1\n[instances.a]\nfmu = "slip.fmu"\n')
    assert main(["simulate", str(tmp_path / "s.toml"), "-o", str(tmp_path / "r.csv")]) == 1
    assert main(["validate", str(fmu)]) == 1
    err = capsys.readouterr().err
    assert err.count("unsafe archive member '../../slip.txt': member path contains '..'") == 2
    assert not (tmp_path.parent / "slip.txt").exists() and not (tmp_path / "slip.txt").exists()


def test_a_member_listed_twice_is_accepted_when_both_copies_are_the_same_and_refused_when_they_differ(tmp_path):
    # as CMake's zip writer lists a member twice (the Reference FMUs' Roberts model)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zipfile warns of the duplicate name it is asked to write
        same = make_zip(tmp_path / "same.fmu", [("modelDescription.xml", MD, None), ("resources/a.txt", b"one", None),
                                                ("resources/a.txt", b"one", None)])
        different = make_zip(tmp_path / "different.fmu", [("modelDescription.xml", MD, None), ("resources/a.txt", b"one", None),
                                                          ("resources/a.txt", b"two", None)])
    dest = extract_fmu(same, tmp_path / "s")
    assert (dest / "resources" / "a.txt").read_bytes() == b"one"
    with pytest.raises(RobogenError) as exc:
        extract_fmu(different, tmp_path / "d")
    assert exc.value.diagnostics[0].message == "archive member 'resources/a.txt' appears twice with different contents"


def test_the_master_extracts_only_what_it_runs_an_fmu_from_and_checks_every_member(tmp_path):
    members = [("modelDescription.xml", MD, None), ("binaries/x86_64-linux/m.so", b"elf", None),
               ("resources/data.txt", b"1", None), ("sources/m.c", b"int x;", None), ("documentation/index.html", b"", None)]
    folder = extract_fmu(make_zip(tmp_path / "m.fmu", members), tmp_path / "m", wanted=needed_to_run)
    assert sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()) == [
        "binaries/x86_64-linux/m.so", "modelDescription.xml", "resources/data.txt"]
    bad = make_zip(tmp_path / "bad.fmu", [*members, ("sources/../../evil.c", b"", None)])
    with pytest.raises(RobogenError) as exc:
        extract_fmu(bad, tmp_path / "bad", wanted=needed_to_run)
    assert exc.value.diagnostics[0].message == "unsafe archive member 'sources/../../evil.c': member path contains '..'"
