"""``robogen package-py``: a Python model class -> an FMI 3.0 Co-Simulation FMU.

The archive holds:

- ``modelDescription.xml`` written from the class's declarations (:mod:`.description`);
- ``binaries/x86_64-linux/<modelIdentifier>.so``: three C translation units linked against the
  building interpreter's shared libpython: ``shim.c`` (the 75 ``fmi3*`` functions),
  ``start_python.c`` (interpreter start-up) and the module cffi generates in embedding mode
  from ``bridge.h`` with ``_embedded.py`` as its init code. The cffi module's name is unique
  per model description, so several Python FMUs share one process;
- ``resources/pyfmu.json`` (module, class, settings, token), ``resources/python/`` (the model's
  module and every first-party module it imports, found by reading their import statements),
  and the files the class adds through ``package_resources()``;
- ``documentation/externalDependencies.txt``: what the binary needs at run time.
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import importlib.metadata
import importlib.util
import json
import os
import re
import sys
import sysconfig
import tempfile
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from robogen import toolchain
from robogen.diagnostics import RobogenError, Span, did_you_mean
from robogen.fmu.archive import write_fmu
from robogen.fmu.headers import PLATFORM_TUPLE, include_dir
from robogen.fmu.platforms import HOST, Platform
from robogen.fmu.modeldesc_writer import write_model_description
from robogen.outputs import output_file
from robogen.pyfmu.description import model_description
from robogen.pyfmu.model import DeclarationError, Model

HERE = Path(__file__).resolve().parent
RUNTIME_MODULES = ("robogen.pyfmu.slave", "robogen.pyfmu.model")
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


@dataclass
class Packaged:
    path: Path
    model_identifier: str
    instantiation_token: str
    files: list[str] = field(default_factory=list)


# --------------------------------------------------------------------------------------------
# The model class and its settings


def load_model_class(spec: str) -> type[Model]:
    """``package.module:Class`` -> the class, or a RobogenError saying what is wrong (an import
    that fails, or a declaration the class makes wrongly, is located in the user's code)."""
    module_name, sep, class_name = spec.partition(":")
    if not sep or not module_name or not class_name:
        raise RobogenError.at(f"'{spec}' is not MODULE:CLASS (e.g. robogen.platforms.ur5e:UR5ePlatform)", None)
    if os.getcwd() not in sys.path and "" not in sys.path:  # as `python -m` would
        sys.path.insert(0, os.getcwd())
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name and module_name.startswith(exc.name):
            raise RobogenError.at(f"no module named '{module_name}' (is it on PYTHONPATH?)", None) from None
        raise RobogenError.at(f"importing '{module_name}' failed: {exc}", _user_code(exc)) from None
    except SyntaxError as exc:
        span = Span.point(exc.filename, exc.lineno, exc.offset or 1) if exc.filename and exc.lineno else None
        raise RobogenError.at(f"syntax error in '{module_name}': {exc.msg}", span) from None
    except DeclarationError as exc:
        raise RobogenError.at(f"a declaration in '{module_name}' is not valid: {exc}", _user_code(exc)) from None
    except (Exception, SystemExit) as exc:  # the user's module raised while it was imported
        raise RobogenError.at(f"importing '{module_name}' failed: {type(exc).__name__}: {exc}", _user_code(exc)) from None
    cls = getattr(module, class_name, None)
    if cls is None:
        names = [n for n, v in vars(module).items() if isinstance(v, type) and issubclass(v, Model) and v is not Model]
        raise RobogenError.at(f"module '{module_name}' has no class '{class_name}'{did_you_mean(class_name, names)}",
                              None)
    if not (isinstance(cls, type) and issubclass(cls, Model)) or cls is Model:
        raise RobogenError.at(f"'{spec}' is not a subclass of robogen.pyfmu.Model", None)
    return cls


def _package_resources(cls: type[Model]) -> dict[str, bytes]:
    """The class's extra resources; its own failure is located in its code."""
    try:
        return cls.package_resources()
    except RobogenError:
        raise
    except Exception as exc:
        raise RobogenError.at(f"{cls.__name__}.package_resources() failed: {type(exc).__name__}: {exc}",
                              _user_code(exc)) from None


def _user_code(exc: BaseException) -> Span | None:
    """Where in the user's code ``exc`` was raised: its innermost frame outside robogen's own
    package and the import machinery (for a declaration error, the class statement)."""
    own = str(HERE.parent)
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if not f.filename.startswith(own) and not f.filename.startswith("<")]
    return Span.point(frames[-1].filename, frames[-1].lineno or 1) if frames else None


def parse_settings(cls: type[Model], assignments: Iterable[str]) -> dict[str, object]:
    """``["name=value", ...]`` -> parsed values, checked against the class's Settings."""
    declared = cls.settings()
    values: dict[str, object] = {}
    for item in assignments:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise RobogenError.at(f"--set {item!r}: expected NAME=VALUE", None)
        setting = declared.get(name)
        if setting is None:
            known = ", ".join(sorted(declared)) or "none"
            raise RobogenError.at(f"--set {name}: {cls.__name__} has no setting '{name}'"
                                  f"{did_you_mean(name, declared)} (settings: {known})", None)
        try:
            values[name] = setting.parse(text.strip())
        except ValueError as exc:
            raise RobogenError.at(f"--set {name}={text}: {exc}", None) from None
    for name, setting in declared.items():
        if setting.required and name not in values:
            raise RobogenError.at(f"{cls.__name__} needs --set {name}=VALUE: the setting '{name}' has no default "
                                  f"({setting.description})", None)
    return values


# --------------------------------------------------------------------------------------------
# The Python code that travels in resources/python


def _installed_roots() -> list[Path]:
    paths = sysconfig.get_paths()
    roots = {paths["stdlib"], paths["platstdlib"], paths["purelib"], paths["platlib"], sys.base_prefix, sys.prefix}
    return [Path(r).resolve() for r in roots if r]


def _first_party(name: str, origin: Path, installed: Sequence[Path]) -> bool:
    if name.split(".")[0] == "robogen":
        return True
    return not any(origin.is_relative_to(root) for root in installed)


def _module_file(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError, AttributeError):
        return None
    if spec is None or not spec.origin or not spec.has_location or not spec.origin.endswith(".py"):
        return None
    return Path(spec.origin).resolve()


def _imports(path: Path, module: str, is_package: bool) -> set[str]:
    tree = ast.parse(path.read_bytes(), str(path))
    package = module if is_package else module.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                base_parts = parts[: len(parts) - node.level + 1]
                base = ".".join(base_parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base:
                found.add(base)
                found.update(f"{base}.{alias.name}" for alias in node.names if alias.name != "*")
    return found


def collect_python(module_name: str, extra_roots: Sequence[str] = RUNTIME_MODULES) -> dict[str, Path]:
    """Archive path under ``resources/python/`` -> source file, for ``module_name``, the runtime
    modules, every first-party module they import (transitively) and their packages."""
    installed = _installed_roots()
    files: dict[str, Path] = {}
    pending = [module_name, *extra_roots]
    seen: set[str] = set()
    while pending:
        name = pending.pop()
        if name in seen:
            continue
        seen.add(name)
        origin = _module_file(name)
        if origin is None or not _first_party(name, origin, installed):
            continue
        is_package = origin.name == "__init__.py"
        relative = name.replace(".", "/") + ("/__init__.py" if is_package else ".py")
        files[relative] = origin
        parent = name.rpartition(".")[0]
        if parent:
            pending.append(parent)
        pending.extend(_imports(origin, name, is_package))
    return dict(sorted(files.items()))


# --------------------------------------------------------------------------------------------
# The binary


def _c_string(text: str) -> str:
    out = []
    for byte in text.encode("utf-8"):
        ch = chr(byte)
        if ch in '"\\':
            out.append("\\" + ch)
        elif 32 <= byte < 127:
            out.append(ch)
        else:
            out.append(f"\\{byte:03o}")
    return '"' + "".join(out) + '"'


def _bridge_declarations() -> tuple[str, str]:
    """(Python-implemented prototypes, C-implemented prototypes) from bridge.h, for cffi."""
    text = (HERE / "bridge.h").read_text()

    def section(title: str) -> list[str]:
        body = text.split(f"/* BEGIN {title} */", 1)[1].split(f"/* END {title} */", 1)[0]
        body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
        return [p.strip() + ";" for p in body.split(";") if p.strip()]

    python = "\n".join('extern "Python+C" ' + p for p in section("implemented in Python"))
    return python, "\n".join(section("implemented in C"))


def _python_build_info() -> dict[str, str]:
    config = sysconfig.get_config_vars()
    if not config.get("Py_ENABLE_SHARED"):
        raise RobogenError.at(
            f"package-py needs a Python built with a shared libpython; {sys.executable} links it statically "
            "(pyenv: PYTHON_CONFIGURE_OPTS=--enable-shared)", None)
    return {
        "soname": str(config.get("INSTSONAME") or config.get("LDLIBRARY")),
        "libdir": str(config["LIBDIR"]),
        "library": "python" + str(config.get("LDVERSION") or config["VERSION"]),
        "include": sysconfig.get_paths()["include"],
        "home": sys.base_prefix,
        "version": f"{sys.version_info.major}.{sys.version_info.minor}",
    }


def site_dirs() -> list[str]:
    """The site-packages folders of the building environment, recorded in the binary."""
    dirs = []
    for key in ("purelib", "platlib"):
        path = sysconfig.get_paths()[key]
        if path not in dirs:
            dirs.append(path)
    return dirs


def build_binary(model_identifier: str, token: str, workdir: Path, *, promote_libpython: bool = True) -> Path:
    """Compile and link ``<workdir>/<model_identifier>.so``.

    ``promote_libpython=False`` leaves out the RTLD_GLOBAL constructor (tests use it to show the
    trap it fixes).
    """
    import cffi
    from cffi.recompiler import make_c_source

    info = _python_build_info()
    module = f"_pyfmu_{model_identifier}_{hashlib.sha256(token.encode()).hexdigest()[:12]}"
    python_decls, c_decls = _bridge_declarations()
    ffi = cffi.FFI()
    ffi.embedding_api("")
    ffi.cdef(python_decls + "\n" + c_decls)
    source = '#include "bridge.h"\nint pyfmu_cffi_start(void) { return cffi_start_python(); }\n'
    ffi.set_source(module, source)
    init_code = (HERE / "_embedded.py").read_text()
    config = {"token": token, "site_dirs": site_dirs()}
    init_code += f"\n\nfrom {module} import ffi as _ffi, lib as _lib\nbind(_ffi, _lib, {config!r})\n"
    ffi.embedding_init_code(init_code)
    workdir.mkdir(parents=True, exist_ok=True)
    generated = workdir / f"{module}.c"
    make_c_source(ffi, module, source, str(generated), verbose=False)
    sites = ", ".join(_c_string(d) for d in config["site_dirs"])
    (workdir / "pyfmu_config.h").write_text(
        f"#define PYFMU_PYTHON_HOME {_c_string(info['home'])}\n"
        f"#define PYFMU_PYTHON_VERSION {_c_string(info['version'])}\n"
        f"#define PYFMU_SITE_DIRS {{{sites}{', ' if sites else ''}NULL}}\n")

    # Reproducible: no temporary folder names (__FILE__ in cffi's code) and no build id.
    prefix_maps = [f"-ffile-prefix-map={workdir}=.", f"-ffile-prefix-map={HERE}=robogen/pyfmu"]
    includes = toolchain.include_args([HERE, workdir, info["include"]])
    shim_defines = [f"-DPYFMU_LIBPYTHON={_c_string(info['soname'])}"] if promote_libpython else []
    ours = [*toolchain.CFLAGS, *toolchain.PIC, *toolchain.OPTIMISE, *prefix_maps]
    foreign = [*toolchain.FOREIGN_CFLAGS, *toolchain.PIC, *toolchain.OPTIMISE, *prefix_maps]
    toolchain.run_compilers([
        [*ours, *shim_defines, "-I", str(include_dir()), *includes, "-c", str(HERE / "shim.c"), "-o", str(workdir / "shim.o")],
        [*ours, *includes, "-c", str(HERE / "start_python.c"), "-o", str(workdir / "start_python.o")],
        [*foreign, *includes, "-c", str(generated), "-o", str(workdir / "module.o")],
    ], f"the Python FMU '{model_identifier}'")
    target = workdir / f"{model_identifier}.so"
    toolchain.run_compiler([*prefix_maps, *toolchain.SHARED, "-o", str(target),
                            str(workdir / "shim.o"), str(workdir / "start_python.o"), str(workdir / "module.o"),
                            "-L", info["libdir"], f"-l{info['library']}", f"-Wl,-rpath,{info['libdir']}",
                            "-Wl,-z,nodelete",  # never unmapped: the interpreter keeps references into it
                            "-Wl,-z,defs", "-Wl,--build-id=none", "-ldl"], f"the Python FMU '{model_identifier}'")
    return target


# --------------------------------------------------------------------------------------------
# The archive


def _host_only(platforms: Sequence[Platform]) -> None:
    """A Python FMU runs its model in the CPython that built it: the binary links that
    interpreter's libpython and finds its standard library and site-packages by the paths of
    this machine, so it exists for this machine's platform only."""
    others = [p.name for p in platforms if p != HOST]
    if others:
        raise RobogenError.at(
            f"a Python FMU is built for {HOST.name} only, not {', '.join(others)}: its binary embeds this machine's "
            f"CPython (it links {sysconfig.get_config_var('LDLIBRARY') or 'libpython'} and loads the model's "
            "packages from this machine's site-packages), which no other platform has. Package a RoboChart/RoboSim "
            "model with `robogen package --platforms` for binaries of every platform", None)


def external_dependencies(info: Mapping[str, str]) -> str:
    def version(dist: str) -> str:
        try:
            return importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            return "not installed"

    lines = [
        "This FMU is implemented in Python (robogen package-py, cffi embedding mode).",
        "",
        f"Python {info['version']} as a shared library: the binary needs {info['soname']}",
        f"  (found at build time in {info['libdir']}, recorded as RUNPATH) and that Python's",
        f"  standard library (home {info['home']}; set PYTHONHOME to use another installation",
        f"  of Python {info['version']}). In a host that already runs Python, it must be Python {info['version']}.",
        "",
        "Python packages, importable at run time (versions at build time):",
        f"  cffi {version('cffi')}",
    ]
    for dist in ("numpy", "pybullet"):
        lines.append(f"  {dist} {version(dist)} (if the model imports it)")
    lines += [
        "  They are looked up in the host's sys.path and then in the build environment's",
        "  site-packages, recorded in the binary:",
        *(f"    {d}" for d in site_dirs()),
        "",
        "The model's own Python code is in resources/python/; resources/pyfmu.json names the class.",
        "",
    ]
    return "\n".join(lines)


def package(spec: str, output: str | os.PathLike, assignments: Iterable[str] = (),
            model_identifier: str | None = None, *, promote_libpython: bool = True,
            platforms: Sequence[Platform] = (HOST,)) -> Packaged:
    """Write the FMU for ``spec`` (``module:Class``) to ``output``, for the host only."""
    _host_only(platforms)
    output = Path(output)
    if output.suffix != ".fmu":
        raise RobogenError.at(f"the output '{output}' must end in .fmu", None)
    output_file(output)
    cls = load_model_class(spec)
    values = parse_settings(cls, assignments)
    configured = cls.configured(values)
    identifier = model_identifier or cls.model_identifier or output.stem
    if not _IDENTIFIER.match(identifier):
        raise RobogenError.at(f"modelIdentifier '{identifier}' is not a C identifier "
                              "(set the class's model_identifier or use --model-identifier)", None)
    description = model_description(configured, identifier)
    token = description.instantiation_token
    module_name, _, class_name = spec.partition(":")
    info = _python_build_info()

    files: dict[str, bytes | str | os.PathLike] = {
        "modelDescription.xml": write_model_description(description),
        "documentation/externalDependencies.txt": external_dependencies(info),
        "resources/pyfmu.json": json.dumps({"module": module_name, "class": class_name, "settings": values,
                                            "instantiationToken": token}, indent=2, sort_keys=True) + "\n",
    }
    for relative, source in collect_python(module_name).items():
        files[f"resources/python/{relative}"] = source
    for name, data in _package_resources(configured).items():
        files[f"resources/{name}"] = data

    with tempfile.TemporaryDirectory(prefix="robogen-pyfmu-") as tmp:
        binary = build_binary(identifier, token, Path(tmp), promote_libpython=promote_libpython)
        files[f"binaries/{PLATFORM_TUPLE}/{identifier}.so"] = binary.read_bytes()
        write_fmu(output, files)
    return Packaged(output, identifier, token, sorted(files))

