"""Checking an .fmu: archive safety and layout, the FMI 3.0 XSD, fmpy's checks, the clock
rules of the FMI 3.0 standard (clocks and their kinds, clocked variables, ModelStructure) that
neither fmpy nor fmutool check, and every binary the FMU carries: in ``binaries/<tuple>/`` a
shared library of the tuple's format (ELF, PE, Mach-O) and architecture that exports the 75
FMI 3.0 functions, and nothing else (read with :mod:`robogen.fmu.binaries`, never loaded).

``validate_fmu(path) -> list[Diagnostic]`` returns errors and warnings, each located in a file
inside the archive (``NAME.fmu/modelDescription.xml:LINE``) where a line is known.
``validate_fmu_texts(path)`` also returns the texts of those files, for rendering excerpts.
"""

from __future__ import annotations

import re
import shutil
import tempfile
import zipfile
from pathlib import Path

from lxml import etree

from robogen.diagnostics import Diagnostic, DiagnosticSink, RobogenError, Span, _sort_key
from robogen.fmu.binaries import BinaryError, read_binary
from robogen.fmu.builddesc import read_build_description
from robogen.fmu.extract import check_archive, extract_fmu
from robogen.fmu.headers import include_dir, schema_dir
from robogen.fmu.platforms import HOST, Platform, parse_tuple
from robogen.fmu.modeldesc import STRUCTURE_ORDER, ModelDescription, Variable, parse_xml, read_model_description

TOP_LEVEL = {"modelDescription.xml", "binaries", "sources", "resources", "documentation", "extra", "terminalsAndIcons", "icons"}
TIME_BASED = ("constant", "fixed", "tunable", "changing", "countdown")
KINDS = TIME_BASED + ("triggered",)
FRACTION_ATTRS = ("resolution", "intervalCounter", "shiftCounter")
FMI2_PLATFORMS = ("linux64", "linux32", "win64", "win32", "darwin64")


def fmi3_function_names() -> list[str]:
    """The 75 functions fmi3Functions.h declares (read from fmpy's copy of the header)."""
    text = (include_dir() / "fmi3Functions.h").read_text()
    return re.findall(r"fmi3\w+TYPE\s+(fmi3\w+);", text)


def validate_fmu(path: str | Path) -> list[Diagnostic]:
    return validate_fmu_texts(path)[0]


def validate_fmu_texts(path: str | Path) -> tuple[list[Diagnostic], dict[str, str]]:
    path = Path(path)
    sink = DiagnosticSink()
    texts: dict[str, str] = {}
    whole = Span.whole_file(str(path))
    if not path.is_file():
        return [_error("FMU file not found", whole)], texts
    problems = check_archive(path)
    if problems:
        return problems, texts
    with zipfile.ZipFile(path) as z:
        infos = z.infolist()
    _check_layout(infos, sink, whole)
    tmp = Path(tempfile.mkdtemp(prefix="robogen-validate-"))
    try:
        folder = extract_fmu(path, tmp / "fmu")
        md_path = folder / "modelDescription.xml"
        display = f"{path}/modelDescription.xml"
        if not md_path.is_file():
            sink.error("the archive has no modelDescription.xml at its root", whole)
            return sink.sorted(), texts
        data = md_path.read_bytes()
        texts[display] = data.decode("utf-8", "replace")
        try:
            md = read_model_description(data, display)
        except RobogenError as exc:
            sink.extend(exc.diagnostics)
            return sink.sorted(), texts
        _check_xsd(data, display, "fmi3ModelDescription.xsd", sink)
        _check_fmpy(folder, display, sink)
        check_model_description(md, sink)
        _check_binaries(folder, md, path, sink)
        bd = folder / "sources" / "buildDescription.xml"
        if bd.is_file():
            bd_display = f"{path}/sources/buildDescription.xml"
            texts[bd_display] = bd.read_text("utf-8", "replace")
            _check_build_description(bd.read_bytes(), bd_display, md, folder, sink)
    except RobogenError as exc:
        sink.extend(exc.diagnostics)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return sorted(sink.items, key=_sort_key), texts


def _error(message: str, span: Span | None) -> Diagnostic:
    from robogen.diagnostics import error

    return error(message, span)


# ----------------------------------------------------------------------------------------
# Archive layout (§4)


def _check_layout(infos: list[zipfile.ZipInfo], sink: DiagnosticSink, whole: Span) -> None:
    for info in infos:
        top = info.filename.split("/")[0]
        if top not in TOP_LEVEL:
            sink.warning(f"'{info.filename}' is outside the FMI 3.0 archive layout (use extra/ for other files)", whole)
        if info.extract_version > 20:
            sink.error(f"'{info.filename}' needs ZIP version {info.extract_version / 10:.1f} to extract; FMI allows at most 2.0", whole)
        parts = info.filename.split("/")
        if parts[0] == "binaries" and len(parts) > 2 and parts[1] in FMI2_PLATFORMS:
            sink.error(f"'binaries/{parts[1]}' is an FMI 2.0 platform name; FMI 3.0 uses tuples such as '{HOST.name}'", whole)


# ----------------------------------------------------------------------------------------
# XSD and fmpy


def _check_xsd(data: bytes, display: str, xsd_name: str, sink: DiagnosticSink) -> None:
    try:
        schema = etree.XMLSchema(etree.parse(str(schema_dir() / xsd_name)))
    except (etree.XMLSchemaParseError, OSError) as exc:
        sink.warning(f"cannot load the XSD {xsd_name} from fmpy: {exc}", None)
        return
    doc = parse_xml(data, display)
    if not schema.validate(doc):
        for e in schema.error_log:
            msg = re.sub(r"\{[^}]*\}", "", e.message)
            sink.error(f"XSD: {msg}", Span.point(display, e.line or 1, (e.column or 0) + 1))


def _check_fmpy(folder: Path, display: str, sink: DiagnosticSink) -> None:
    try:
        from fmpy.validation import validate_fmu as fmpy_validate
    except ImportError:  # pragma: no cover - fmpy is a dependency
        return
    try:
        problems = fmpy_validate(str(folder))
    except Exception as exc:  # fmpy's own failures become one message, never a traceback
        problems = [f"fmpy could not read the FMU: {exc}"]
    for p in problems:
        first = str(p).strip().splitlines()[0] if str(p).strip() else str(p)
        if "schema" in first.lower() or first.startswith("Failed to validate"):
            continue  # the XSD check above reports these with lines
        sink.error(f"fmpy: {first}", Span.whole_file(display))


# ----------------------------------------------------------------------------------------
# robogen's rules on the model description (§2.2, §3)


def check_model_description(md: ModelDescription, sink: DiagnosticSink) -> None:
    at = md.span
    by_vr = md.by_vr()
    clocks = [v for v in md.variables if v.is_clock]
    cs = md.co_simulation
    if cs is None:
        sink.error("no <CoSimulation> element: robogen's master imports FMI 3.0 Co-Simulation FMUs", at(1))
    elif clocks and not cs.has_event_mode:
        sink.error(f"the FMU has clocks ({', '.join(c.name for c in clocks[:3])}) but <CoSimulation> lacks hasEventMode=\"true\"", at(cs.line))
    if cs is not None and not cs.might_return_early and cs.can_return_early_after_intermediate_update \
            and not cs.provides_intermediate_update:
        sink.error("canReturnEarlyAfterIntermediateUpdate needs providesIntermediateUpdate", at(cs.line))

    for v in clocks:
        _check_clock(v, sink, at)
    previous_seen: dict[int, str] = {}
    for v in md.variables:
        if v.clocks:
            for vr in v.clocks:
                target = by_vr.get(vr)
                if target is None:
                    sink.error(f"'{v.name}': clocks=\"{' '.join(map(str, v.clocks))}\" names value reference {vr}, which no variable has", at(v.line))
                elif not target.is_clock:
                    sink.error(f"'{v.name}': clocks= names '{target.name}' (value reference {vr}), which is a {target.type}, not a Clock", at(v.line))
            if len(v.clocks) > 1:
                sink.warning(f"'{v.name}' has {len(v.clocks)} clocks; robogen keeps one clock per clocked variable (some importers reject more)", at(v.line))
            if not v.is_clock and v.variability not in ("discrete", "tunable"):
                sink.error(f"clocked variable '{v.name}' has variability=\"{v.variability}\"; clocked variables are discrete or tunable", at(v.line))
        if v.previous is not None:
            prev = by_vr.get(v.previous)
            if v.is_clock:
                sink.error(f"clock '{v.name}' cannot have previous= (clocks are not clocked states)", at(v.line))
            elif prev is None:
                sink.error(f"'{v.name}': previous=\"{v.previous}\" names no variable", at(v.line))
            elif prev is v or prev.value_reference == v.value_reference:
                sink.error(f"'{v.name}': previous= names the variable itself", at(v.line))
            elif prev.type != v.type or prev.variability != "discrete" or prev.causality == "input":
                sink.error(f"'{v.name}': previous= must name a discrete, non-input variable of type {v.type}; '{prev.name}' is {prev.variability} {prev.causality} {prev.type}", at(v.line))
            elif v.previous in previous_seen:
                sink.error(f"'{v.name}' and '{previous_seen[v.previous]}' share previous=\"{v.previous}\"", at(v.line))
            previous_seen.setdefault(v.previous, v.name)
    _check_structure(md, sink)


def _check_clock(v: Variable, sink: DiagnosticSink, at) -> None:
    a, kind = v.attributes, v.interval_variability
    where = at(v.line)
    if v.variability != "discrete":
        sink.error(f"clock '{v.name}' has variability=\"{v.variability}\"; clocks are discrete", where)
    if kind not in KINDS:
        sink.error(f"clock '{v.name}' needs intervalVariability (one of {', '.join(KINDS)})", where)
        return
    if v.causality == "output" and kind != "triggered":
        sink.error(f"output clock '{v.name}' is {kind}; output clocks must be triggered", where)
    if kind in TIME_BASED and v.causality != "input":
        sink.error(f"{kind} clock '{v.name}' has causality=\"{v.causality}\"; time-based clocks are inputs", where)
    for attr in ("start", "initial", "previous", "intermediateUpdate"):
        if attr in a:
            sink.error(f"clock '{v.name}' has {attr}=; a Clock has none", where)
    if kind == "constant" and v.interval is None:
        sink.error(f"constant clock '{v.name}' needs intervalDecimal", where)
    if kind in ("fixed", "tunable") and v.interval is None:
        sink.warning(f"{kind} clock '{v.name}' has no intervalDecimal (required by the 3.0.2 text; robogen emits it and uses 'constant')", where)
    if kind in ("changing", "countdown", "triggered"):
        for attr in ("intervalDecimal", "shiftDecimal") + FRACTION_ATTRS:
            if attr in a:
                sink.error(f"{kind} clock '{v.name}' must not have {attr}", where)
    if kind == "triggered" and "supportsFraction" in a:
        sink.error(f"triggered clock '{v.name}' must not have supportsFraction", where)
    if v.interval is not None and v.interval <= 0:
        sink.error(f"clock '{v.name}': intervalDecimal must be > 0", where)
    if v.shift is not None and v.shift < 0:
        sink.error(f"clock '{v.name}': shiftDecimal must be >= 0", where)
    if "shiftDecimal" in a and "intervalDecimal" not in a and kind in ("constant", "fixed", "tunable"):
        sink.error(f"clock '{v.name}': shiftDecimal needs intervalDecimal", where)
    if any(x in a for x in FRACTION_ATTRS) and a.get("supportsFraction") != "true":
        sink.error(f"clock '{v.name}': resolution/intervalCounter/shiftCounter need supportsFraction=\"true\"", where)
    if v.causality == "output" and "priority" in a:
        sink.error(f"output clock '{v.name}' must not have priority", where)


def _check_structure(md: ModelDescription, sink: DiagnosticSink) -> None:
    at = md.span
    by_vr = md.by_vr()
    rank = -1
    for u in md.unknowns:
        if u.kind not in STRUCTURE_ORDER:
            continue
        r = STRUCTURE_ORDER.index(u.kind)
        if r < rank:
            sink.error(f"<{u.kind}> after <{STRUCTURE_ORDER[rank]}>: ModelStructure lists {', '.join(STRUCTURE_ORDER)} in that order", at(u.line))
        rank = max(rank, r)
        var = by_vr.get(u.value_reference)
        if var is None:
            sink.error(f"<{u.kind} valueReference=\"{u.value_reference}\"> names no variable", at(u.line))
            continue
        if var.is_clock and var.causality == "local":
            sink.error(f"local clock '{var.name}' must not appear in ModelStructure", at(u.line))
        if u.kind == "Output" and var.causality != "output":
            sink.error(f"<Output> lists '{var.name}', whose causality is {var.causality}", at(u.line))
        if u.kind == "ClockedState" and (not var.clocks or var.previous is None):
            sink.error(f"<ClockedState> lists '{var.name}', which is not a clocked variable with previous=", at(u.line))
        if u.kind == "InitialUnknown" and var.clocks:
            sink.warning(f"<InitialUnknown> lists the clocked variable '{var.name}' (legal, but fmpy's validator rejects it)", at(u.line))
        for d in u.dependencies or ():
            if d not in by_vr:
                sink.error(f"<{u.kind}> for '{var.name}' depends on value reference {d}, which no variable has", at(u.line))
    listed = {u.value_reference for u in md.unknowns if u.kind == "Output"}
    for v in md.variables:
        if v.causality == "output" and v.value_reference not in listed:
            sink.error(f"output {'clock ' if v.is_clock else ''}'{v.name}' is missing from <ModelStructure><Output>", at(v.line))
    states = {u.value_reference for u in md.unknowns if u.kind == "ClockedState"}
    for v in md.variables:
        if v.clocks and v.previous is not None and not v.is_clock and v.value_reference not in states:
            sink.error(f"clocked state '{v.name}' is missing from <ModelStructure><ClockedState>", at(v.line))


# ----------------------------------------------------------------------------------------
# Binary (§5) and build description (§4)


def _check_binaries(folder: Path, md: ModelDescription, fmu: Path, sink: DiagnosticSink) -> None:
    """Each platform folder of ``binaries/`` holds the FMU's library for that platform."""
    base = folder / "binaries"
    if md.co_simulation is None or not base.is_dir():
        return
    ident = md.co_simulation.model_identifier
    names = sorted(p.name for p in base.iterdir() if p.is_dir())
    if HOST.name not in names:
        sink.warning(f"no binary for {HOST.name}: {HOST.binary(ident)} is missing", Span.whole_file(str(fmu)))
    for name in names:
        platform = parse_tuple(name)
        if platform is None:
            if name not in FMI2_PLATFORMS:  # those the layout check reports
                sink.warning(f"'binaries/{name}' is not an FMI 3.0 platform tuple (<arch>-<sys>, such as "
                             f"'{HOST.name}'); its files are not checked", Span.whole_file(str(fmu)))
            continue
        library = folder / platform.binary(ident)
        if not library.is_file():
            sink.error(f"'binaries/{name}' holds no {library.name}, the library of modelIdentifier '{ident}' "
                       f"for {name}", Span.whole_file(str(fmu)))
            continue
        check_binary(library.read_bytes(), platform, ident, sink, Span.whole_file(f"{fmu}/{platform.binary(ident)}"))


def check_binary(data: bytes, platform: Platform, model_identifier: str, sink: DiagnosticSink, where: Span) -> None:
    """The library ``data`` of ``model_identifier``, found in ``binaries/<platform>``: its
    format, architecture, kind and exports."""
    try:
        info = read_binary(data, platform.arch)
    except BinaryError as exc:
        sink.error(f"cannot read the binary: {exc}", where)
        return
    if info.format != platform.format or info.arch != platform.arch:
        sink.error(f"the binary is {_article(info.format)} {info.format} file for {info.arch}; binaries/{platform} "
                   f"needs {_article(platform.format)} {platform.format} shared library for {platform.arch}", where)
        return
    if not info.shared:
        sink.error(f"the binary is {_article(info.kind)} {info.kind}, not a shared library: an importer cannot load it", where)
        return
    functions = fmi3_function_names()
    missing = [f for f in functions if f not in info.exports]
    if missing:
        shown = ", ".join(missing[:8]) + (f" and {len(missing) - 8} more" if len(missing) > 8 else "")
        sink.error(f"the binary exports {len(functions) - len(missing)} of the {len(functions)} FMI 3.0 functions; "
                   f"missing: {shown}", where)
    prefixed = sorted(s for s in info.exports if s.startswith(f"{model_identifier}_fmi3"))
    if prefixed:
        sink.error(f"the binary exports prefixed names ({prefixed[0]}, ...): FMI3_FUNCTION_PREFIX must not be defined "
                   "for a shared library", where)
    others = sorted(info.exports - set(functions) - set(prefixed))
    if others:
        shown = ", ".join(others[:5]) + (f" and {len(others) - 5} more" if len(others) > 5 else "")
        sink.warning(f"the binary exports {len(others)} name(s) besides the FMI 3.0 functions ({shown}); they can clash "
                     "with other libraries in the importer's process", where)


def _article(word: str) -> str:
    return "an" if word[0].lower() in "aeiou" else "a"


def _check_build_description(data: bytes, display: str, md: ModelDescription, folder: Path, sink: DiagnosticSink) -> None:
    _check_xsd(data, display, "fmi3BuildDescription.xsd", sink)
    bd = read_build_description(data, display)
    if bd.fmi_version != md.fmi_version:
        sink.error(f"buildDescription fmiVersion=\"{bd.fmi_version}\" differs from the model description's \"{md.fmi_version}\"", bd.at(bd.line))
    configs = bd.configurations
    if not configs:
        sink.error("no <BuildConfiguration>", bd.at(bd.line))
    if sum(1 for c in configs if c.platform is None) > 1:
        sink.error("more than one <BuildConfiguration> without platform=", bd.at(bd.line))
    if len(configs) > 1:
        sink.warning("several <BuildConfiguration>s: fmpy compile reads only the first", bd.at(configs[1].line))
    idents = {md.co_simulation.model_identifier} if md.co_simulation else set()
    for c in configs:
        if idents and c.model_identifier not in idents:
            sink.error(f"<BuildConfiguration modelIdentifier=\"{c.model_identifier}\"> matches no interface's modelIdentifier", bd.at(c.line))
        if len(c.source_sets) > 1:
            sink.warning("several <SourceFileSet>s: fmpy compile reads only the first", bd.at(c.source_sets[1].line))
        for s in c.source_sets:
            for name, line in s.files:
                if not (folder / "sources" / (name or "")).is_file():
                    sink.error(f"<SourceFile name=\"{name}\"> is not in sources/", bd.at(line))
            for d in s.definitions:
                if d.name == "FMI3_FUNCTION_PREFIX":
                    sink.error("FMI3_FUNCTION_PREFIX must not be defined: a shared object exports unprefixed names", bd.at(d.line))
                elif d.value is None:
                    sink.warning(f"<PreprocessorDefinition name=\"{d.name}\"> has no value (fmpy passes it as {d.name}=None)", bd.at(d.line))
