"""The code generator as a library: model files -> FMU sources -> ``.fmu``.

``compile_model`` checks the models, chooses the boundary, draws its machines' diagrams, lowers it
to the IR and writes the FMU's unpacked layout (``modelDescription.xml``, ``sources/``,
``documentation/``); ``build_fmu`` compiles ``sources/`` with the system C compiler against
fmpy's FMI headers and zips the archive. Each stage hands the next a finished product: the
resolved model and the diagrams to lowering and generation, the IR and the diagrams to the
generator, the generated sources (with their modelIdentifier) to the build.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Sequence

from robogen.codegen import binary
from robogen.codegen.generate import CodegenOptions, Generated, generate
from robogen.diagnostics import RobogenError, Span, error
from robogen.fmu.archive import write_fmu
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.ir import model as ir
from robogen.ir.boundary import Boundary, select_boundary
from robogen.ir.lower import LoweringOptions, lower
from robogen.outputs import check_not_input, output_file, output_folder
from robogen.semantics import SemanticModel, check_paths
from robogen.semantics.graph import mermaid


@dataclass
class Compiled:
    fmu: ir.Fmu
    generated: Generated
    folder: Path
    model: SemanticModel


def front_end(paths: Sequence[str | os.PathLike], *, module: str | None = None,
              machine: str | None = None) -> tuple[SemanticModel, Boundary]:
    """Check the models and choose the boundary (raises RobogenError on any problem)."""
    model = check_paths(paths)
    if model.errors:
        raise RobogenError(model.errors)
    return model, select_boundary(model, module=module, machine=machine)


def lower_paths(paths: Sequence[str | os.PathLike], *, module: str | None = None, machine: str | None = None,
                options: LoweringOptions | None = None) -> tuple[ir.Fmu, SemanticModel]:
    """Check the models and lower the chosen boundary (raises RobogenError on any problem)."""
    model, boundary = front_end(paths, module=module, machine=machine)
    return lower(model, boundary, options), model


def diagrams_of(boundary: Boundary) -> list[str]:
    """The Mermaid state diagram of each machine of the boundary, in the order lowering gives
    the machines (their IR index)."""
    return [mermaid(scope) for _, scope, _ in boundary.machines]


def compile_model(paths: Sequence[str | os.PathLike], output: str | os.PathLike | None = None, *,
                  module: str | None = None, machine: str | None = None, options: LoweringOptions | None = None,
                  codegen: CodegenOptions | None = None) -> Compiled:
    """Write the unpacked FMU (everything but the binary) to ``output`` (default build/<Name>)."""
    if output is not None:
        check_not_input(Path(output), _inputs(paths, codegen))
    model, boundary = front_end(paths, module=module, machine=machine)
    if output is not None:
        check_not_input(Path(output), [f.path for f in model.files])  # a model file found in a folder given
    return compile_checked(model, boundary, output, options=options, codegen=codegen, inputs=_inputs(paths, codegen))


def compile_checked(model: SemanticModel, boundary: Boundary, output: str | os.PathLike | None = None, *,
                    options: LoweringOptions | None = None, codegen: CodegenOptions | None = None,
                    inputs: Sequence[str | os.PathLike] = ()) -> Compiled:
    """:func:`compile_model` of a model already checked, with its boundary chosen (``inputs``: the
    files the output may not overwrite). Lowering the model twice, for two semantics, checks it
    once."""
    diagrams = diagrams_of(boundary)
    fmu = lower(model, boundary, options)
    generated = generate(fmu, codegen, diagrams=diagrams)
    folder = Path(output) if output is not None else Path("build") / fmu.model_identifier
    # A new or empty folder, or one robogen wrote before: replace what a previous compile wrote
    # there, keep anything else (e.g. a user's notes).
    output_folder(folder, command="compile", inputs=list(inputs))
    for sub in ("sources", "documentation"):
        if (folder / sub).is_dir():
            shutil.rmtree(folder / sub)
    generated.write(folder)
    for src in binary.runtime_sources():
        shutil.copyfile(src, folder / "sources" / src.name)
    return Compiled(fmu, generated, folder, model)


def _inputs(paths: Sequence[str | os.PathLike], codegen: CodegenOptions | None) -> list[str | os.PathLike]:
    """The files a compilation reads, which no output may overwrite."""
    functions = codegen.functions if codegen is not None else None
    return [*paths, *([functions] if functions is not None else [])]


def model_identifier_of(folder: Path) -> str:
    """The modelIdentifier of an unpacked FMU folder written earlier (`robogen package
    SOURCE_DIR`), from its buildDescription.xml."""
    from xml.etree import ElementTree

    path = folder / "sources" / "buildDescription.xml"
    if not path.is_file():
        raise RobogenError(error(f"{folder} is not an FMU source folder: sources/buildDescription.xml is missing", None))
    try:
        root = ElementTree.parse(path).getroot()
        config = root.find("BuildConfiguration")
        ident = config.get("modelIdentifier") if config is not None else None
    except ElementTree.ParseError as exc:
        line, col = exc.position
        raise RobogenError(error(f"malformed XML: {exc}", Span.point(str(path), line, col + 1))) from None
    if not ident:
        raise RobogenError(error("no BuildConfiguration with a modelIdentifier", Span.whole_file(str(path))))
    return ident


def build_fmu(folder: str | os.PathLike, output: str | os.PathLike, *, model_identifier: str | None = None,
              validate: bool = True) -> Path:
    """Compile ``folder/sources`` into ``binaries/x86_64-linux/<id>.so`` and zip the FMU. The
    modelIdentifier is read from the folder's buildDescription.xml unless given."""
    folder = Path(folder)
    output = output_file(output, inputs=[folder / "modelDescription.xml"])
    for sub in ("sources", "documentation", "resources"):
        if output.resolve().is_relative_to((folder / sub).resolve()):
            raise RobogenError(error(f"-o {output} is inside {folder / sub}, an input of this command; "
                                     "choose a path outside it", None))
    ident = model_identifier or model_identifier_of(folder)
    if not (folder / "modelDescription.xml").is_file():
        raise RobogenError(error(f"{folder}/modelDescription.xml is missing", None))
    with tempfile.TemporaryDirectory(prefix="robogen-build-") as tmp:
        so = binary.compile_fmu_binary(folder / "sources", ident, Path(tmp) / f"{ident}.so")
        files: dict[str, bytes | str | os.PathLike] = {
            "modelDescription.xml": folder / "modelDescription.xml",
            f"binaries/{PLATFORM_TUPLE}/{ident}.so": so.read_bytes(),
        }
        for sub in ("sources", "documentation", "resources"):
            base = folder / sub
            if base.is_dir():
                for path in sorted(base.rglob("*")):
                    if path.is_file():
                        files[f"{sub}/{path.relative_to(base).as_posix()}"] = path
        target = write_fmu(output, files)
    if validate:
        from robogen.fmu.validate import validate_fmu

        problems = [d for d in validate_fmu(target) if d.is_error]
        if problems:
            raise RobogenError(problems)
    return target


def package_model(paths: Sequence[str | os.PathLike], output: str | os.PathLike, *, module: str | None = None,
                  machine: str | None = None, options: LoweringOptions | None = None,
                  codegen: CodegenOptions | None = None, validate: bool = True, work: str | os.PathLike | None = None) -> tuple[Path, Compiled]:
    """Compile the model (into ``work``, default a temporary folder) and package it as ``output``."""
    output = output_file(output, inputs=_inputs(paths, codegen))
    if work is None:
        with tempfile.TemporaryDirectory(prefix="robogen-src-") as tmp:
            compiled = compile_model(paths, Path(tmp) / "fmu", module=module, machine=machine, options=options, codegen=codegen)
            check_not_input(output, [f.path for f in compiled.model.files])  # a model file found in a folder given
            return build_fmu(compiled.folder, output, model_identifier=compiled.generated.model_identifier,
                             validate=validate), compiled
    compiled = compile_model(paths, work, module=module, machine=machine, options=options, codegen=codegen)
    check_not_input(output, [f.path for f in compiled.model.files])
    return build_fmu(compiled.folder, output, model_identifier=compiled.generated.model_identifier, validate=validate), compiled


def parse_time_unit(text: str) -> Fraction:
    try:
        value = Fraction(text)
    except (ValueError, ZeroDivisionError):
        value = Fraction(-1)
    if value <= 0:
        raise RobogenError(error(f"--time-unit must be a positive number of seconds, not {text!r}", None))
    return value


__all__ = ["Compiled", "compile_model", "compile_checked", "build_fmu", "package_model", "front_end", "lower_paths", "diagrams_of", "LoweringOptions", "CodegenOptions",
           "parse_time_unit"]
