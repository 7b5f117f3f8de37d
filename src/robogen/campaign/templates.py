"""The placeholders of a campaign's file templates: ``$NAME`` or ``${NAME}``, the name of a
parameter (which may hold dots and slashes inside braces, ``${platform.sample_period}``)."""

from __future__ import annotations

import string
from typing import Mapping


class _Template(string.Template):
    """``$NAME`` or ``${NAME}``; inside braces a name may hold dots and slashes
    (``${platform.sample_period}``)."""

    braceidpattern = r"[A-Za-z_][A-Za-z0-9_./-]*"


def template_of(text: str) -> string.Template:
    return _Template(text)


def render(text: str, values: Mapping[str, object]) -> str:
    """``text`` with every placeholder replaced by its value (``str()`` of it); KeyError names a
    placeholder without a value."""
    return _Template(text).substitute({k: str(v) for k, v in values.items()})
