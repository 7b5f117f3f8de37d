"""An FMU's ``sources/buildDescription.xml``, read once, with the line of every element.

Packaging a folder ``robogen compile`` wrote takes its modelIdentifier from here, and validation
checks it against the model description: both read this structure, never the XML.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from robogen.diagnostics import RobogenError, Span
from robogen.fmu.modeldesc import parse_xml


@dataclass(frozen=True)
class Definition:
    name: str | None
    value: str | None
    line: int


@dataclass(frozen=True)
class SourceFileSet:
    files: tuple[tuple[str | None, int], ...]  # (name, line)
    definitions: tuple[Definition, ...]
    line: int


@dataclass(frozen=True)
class BuildConfiguration:
    model_identifier: str | None
    platform: str | None
    source_sets: tuple[SourceFileSet, ...]
    line: int


@dataclass(frozen=True)
class BuildDescription:
    display: str  # the path diagnostics name
    fmi_version: str | None
    configurations: tuple[BuildConfiguration, ...]
    line: int

    def at(self, line: int) -> Span:
        return Span.point(self.display, line)

    @property
    def model_identifier(self) -> str:
        """The first configuration's modelIdentifier (the one fmpy compile builds), or a located error."""
        for config in self.configurations[:1]:
            if config.model_identifier:
                return config.model_identifier
        raise RobogenError.at("no BuildConfiguration with a modelIdentifier", Span.whole_file(self.display))


def read_build_description(data: bytes, display: str) -> BuildDescription:
    """Parse the bytes of a buildDescription.xml; malformed XML is a located RobogenError."""
    root = parse_xml(data, display).getroot()
    line = lambda el: el.sourceline or 1  # noqa: E731
    configurations = tuple(
        BuildConfiguration(
            model_identifier=config.get("modelIdentifier"),
            platform=config.get("platform"),
            source_sets=tuple(
                SourceFileSet(
                    files=tuple((f.get("name"), line(f)) for f in s.findall("SourceFile")),
                    definitions=tuple(Definition(d.get("name"), d.get("value"), line(d))
                                      for d in s.findall("PreprocessorDefinition")),
                    line=line(s),
                )
                for s in config.findall("SourceFileSet")
            ),
            line=line(config),
        )
        for config in root.findall("BuildConfiguration")
    )
    return BuildDescription(display, root.get("fmiVersion"), configurations, line(root))


def read_build_description_file(path: Path) -> BuildDescription:
    return read_build_description(path.read_bytes(), str(path))
