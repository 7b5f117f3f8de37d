"""The code generator as a library: model files -> FMU sources -> ``.fmu``.

``compile_model`` checks the models, chooses the boundary, draws its machines' diagrams, lowers it
to the IR and writes the FMU's unpacked layout (``modelDescription.xml``, ``sources/``,
``documentation/``). ``package_model`` goes straight from the models to the archive: the FMU's
files in memory, compiled into a binary per platform asked for (:mod:`robogen.codegen.binary`),
zipped by :func:`robogen.fmu.archive.write_fmu` and validated; ``build_fmu`` does the same from a
folder ``compile_model`` wrote. Each checks its output path once, before any work. Each stage hands
the next a finished product: the resolved model and the diagrams to lowering and generation, the
IR and the diagrams to the generator, the generated files (with their modelIdentifier) to the build.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from robogen.codegen import binary
from robogen.codegen.generate import CodegenOptions, Generated, generate
from robogen.diagnostics import RobogenError, error
from robogen.fmu.archive import write_fmu
from robogen.fmu.builddesc import read_build_description_file
from robogen.fmu.platforms import HOST, Platform
from robogen.ir import model as ir
from robogen.ir.boundary import Boundary, select_boundary
from robogen.ir.lower import LoweringOptions, lower
from robogen.outputs import check_not_input, output_file, output_folder
from robogen.semantics import SemanticModel, check_paths
from robogen.semantics.graph import mermaid


#: An FMU's files by archive path: text, bytes, or a file to copy.
Files = Mapping[str, "str | bytes | os.PathLike"]


@dataclass
class Compiled:
    fmu: ir.Fmu
    generated: Generated
    folder: Path | None  # where compile_model wrote the sources; None when packaged from memory
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
    fmu, generated = _generate(model, boundary, options, codegen)
    folder = Path(output) if output is not None else Path("build") / fmu.model_identifier
    # A new or empty folder, or one robogen wrote before: replace what a previous compile wrote
    # there, keep anything else (e.g. a user's notes).
    output_folder(folder, command="compile", inputs=list(inputs))
    for sub in ("sources", "documentation"):
        if (folder / sub).is_dir():
            shutil.rmtree(folder / sub)
    generated.write(folder)
    for name, src in _runtime_files().items():
        shutil.copyfile(src, folder / name)
    return Compiled(fmu, generated, folder, model)


def _generate(model: SemanticModel, boundary: Boundary, options: LoweringOptions | None,
              codegen: CodegenOptions | None) -> tuple[ir.Fmu, Generated]:
    fmu = lower(model, boundary, options)
    return fmu, generate(fmu, codegen, diagrams=diagrams_of(boundary))


def fmu_files(generated: Generated) -> dict[str, str | Path]:
    """Every file of the FMU but its binaries, by archive path: the generated files, and the
    runtime's sources copied into ``sources/``."""
    return {**generated.files, **_runtime_files()}


def _runtime_files() -> dict[str, Path]:
    return {f"sources/{src.name}": src for src in binary.runtime_sources()}


def _inputs(paths: Sequence[str | os.PathLike], codegen: CodegenOptions | None) -> list[str | os.PathLike]:
    """The files a compilation reads, which no output may overwrite."""
    functions = codegen.functions if codegen is not None else None
    return [*paths, *([functions] if functions is not None else [])]


def model_identifier_of(folder: Path) -> str:
    """The modelIdentifier of an unpacked FMU folder written earlier (`robogen package
    SOURCE_DIR`), from its buildDescription.xml."""
    path = folder / "sources" / "buildDescription.xml"
    if not path.is_file():
        raise RobogenError(error(f"{folder} is not an FMU source folder: sources/buildDescription.xml is missing", None))
    return read_build_description_file(path).model_identifier


def build_fmu(folder: str | os.PathLike, output: str | os.PathLike, *, model_identifier: str | None = None,
              platforms: Sequence[Platform] = (HOST,), validate: bool = True) -> Path:
    """Package the FMU folder ``robogen compile`` wrote: its files, read into memory, and a binary
    per platform compiled from its ``sources/``. The modelIdentifier is read from the folder's
    buildDescription.xml unless given."""
    folder = Path(folder)
    if not (folder / "modelDescription.xml").is_file():
        raise RobogenError(error(f"{folder}/modelDescription.xml is missing", None))
    read = [folder / "modelDescription.xml"]
    subfolders = [folder / sub for sub in ("sources", "documentation", "resources") if (folder / sub).is_dir()]
    read += [path for base in subfolders for path in sorted(base.rglob("*")) if path.is_file()]
    output = _output(output, read, subfolders)
    ident = model_identifier or model_identifier_of(folder)
    files = {path.relative_to(folder).as_posix(): path.read_bytes() for path in read}
    return _package(files, ident, output, platforms, validate)


def package_model(paths: Sequence[str | os.PathLike], output: str | os.PathLike, *, module: str | None = None,
                  machine: str | None = None, options: LoweringOptions | None = None,
                  codegen: CodegenOptions | None = None, platforms: Sequence[Platform] = (HOST,),
                  validate: bool = True) -> tuple[Path, Compiled]:
    """Check, lower and generate the model, compile a binary for each of ``platforms`` and write
    the validated FMU ``output``: files in memory -> compilers -> archive."""
    model, boundary = front_end(paths, module=module, machine=machine)
    # the model files found in a folder given are inputs too
    output = _output(output, [*_inputs(paths, codegen), *(f.path for f in model.files)])
    fmu, generated = _generate(model, boundary, options, codegen)
    target = _package(fmu_files(generated), generated.model_identifier, output, platforms, validate)
    return target, Compiled(fmu, generated, None, model)


def _output(output: str | os.PathLike, inputs: Iterable[str | os.PathLike], folders: Iterable[Path] = ()) -> Path:
    """The one check of an FMU output: no input, no folder, nothing inside an input folder."""
    path = output_file(output, inputs=inputs)
    for folder in folders:
        if path.resolve().is_relative_to(folder.resolve()):
            raise RobogenError(error(f"-o {path} is inside {folder}, an input of this command; "
                                     "choose a path outside it", None))
    return path


def _package(files: Files, model_identifier: str, output: Path, platforms: Sequence[Platform], validate: bool) -> Path:
    sources = {name.removeprefix("sources/"): content for name, content in files.items() if name.startswith("sources/")}
    binaries = binary.build_binaries(sources, model_identifier, platforms)
    target = write_fmu(output, {**files, **binaries})
    if validate:
        from robogen.fmu.validate import validate_fmu

        problems = [d for d in validate_fmu(target) if d.is_error]
        if problems:
            raise RobogenError(problems)
    return target


def parse_time_unit(text: str) -> Fraction:
    try:
        value = Fraction(text)
    except (ValueError, ZeroDivisionError):
        value = Fraction(-1)
    if value <= 0:
        raise RobogenError(error(f"--time-unit must be a positive number of seconds, not {text!r}", None))
    return value


__all__ = ["Compiled", "compile_model", "compile_checked", "fmu_files", "build_fmu", "package_model", "front_end", "lower_paths",
           "diagrams_of", "LoweringOptions", "CodegenOptions", "parse_time_unit"]
