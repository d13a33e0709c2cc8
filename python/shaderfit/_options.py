"""The search's keyword arguments: the library's options by their own names (described once, in
include/shaderfit/search/options.hpp), plus the few short names of ``search()``'s signature."""

from __future__ import annotations

import numbers
import os
from typing import Any, Mapping

from . import _shaderfit

# search()'s short keywords and the options they stand for.
ALIASES = {
    "time": "time_limit_s",
    "ops": "operators",
    "evolve_ops": "evolution_operators",
    "baselines": "start",
    "evals": "max_candidates",
}

FIELDS = {f["name"]: f for f in _shaderfit.option_fields()}


def _type_error(name: str, expected: str, value: Any) -> TypeError:
    return TypeError(f"{name}: expected {expected}, got {type(value).__name__} {value!r}")


def _number(name: str, v: Any) -> str:
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise _type_error(name, "a number", v)
    return repr(float(v))


def _integer(name: str, v: Any) -> str:
    if isinstance(v, bool) or not isinstance(v, numbers.Integral):
        raise _type_error(name, "an integer", v)
    return str(int(v))


def option_text(keyword: str, field: Mapping[str, Any], v: Any) -> str:
    """The value as the library's text form of the option (search_option_text)."""
    kind = field["kind"]
    if v is None:
        if field["may_be_empty"]:
            return "none" if kind == "operators" else ""
        raise _type_error(keyword, f"a value ({kind})", v)
    if kind == "real":
        return _number(keyword, v)
    if kind == "integer":
        return _integer(keyword, v)
    if kind == "bool":
        if not isinstance(v, (bool,)) and type(v).__name__ != "bool_":
            raise _type_error(keyword, "True or False", v)
        return "true" if v else "false"
    if kind == "text":
        if isinstance(v, os.PathLike):
            return os.fspath(v)
        if not isinstance(v, str):
            raise _type_error(keyword, "a path", v)
        return v
    if kind == "stop target":
        if isinstance(v, Mapping):
            v = (v.get("max_loss"), v.get("max_cost"))
        if not isinstance(v, (tuple, list)) or len(v) != 2:
            raise _type_error(keyword, "(max_loss, max_cost)", v)
        return f"{_number(keyword, v[0])},{_number(keyword, v[1])}"
    if kind == "reals":
        if isinstance(v, str):
            return v
        return ",".join(_number(keyword, x) for x in v)
    if kind == "formulas":
        formulas = [v] if isinstance(v, str) else list(v)
        for f in formulas:
            if not isinstance(f, str):
                raise _type_error(keyword, "formulas (text)", f)
            if ";" in f:
                raise ValueError(f"{keyword}: a formula may not hold ';': {f!r}")
        return ";".join(formulas)
    if kind == "names":
        names = [v] if isinstance(v, str) else list(v)
        for n in names:
            if not isinstance(n, str):
                raise _type_error(keyword, "input names (text)", n)
        return ",".join(names)
    if kind == "operators":
        if isinstance(v, str):
            return v
        ops = list(v)
        for op in ops:
            if not isinstance(op, str):
                raise _type_error(keyword, "operator names", op)
        if not ops:
            return "none" if field["may_be_empty"] else ""
        return ",".join(ops)
    if kind == "choice":
        if not isinstance(v, str):
            raise _type_error(keyword, f"one of {field['choices']}", v)
        return v
    raise AssertionError(f"unknown option kind {kind}")


class Options:
    """Keyword arguments resolved to the library's fields, remembering which keyword set each."""

    def __init__(self, keywords: Mapping[str, Any], function: str = "search()"):
        self.texts: dict[str, str] = {}
        self.keyword: dict[str, str] = {}  # field -> the keyword that set it
        for key, value in keywords.items():
            field_name = ALIASES.get(key, key)
            field = FIELDS.get(field_name)
            if field is None:
                known = ", ".join(list(ALIASES) + sorted(FIELDS))
                raise TypeError(f"{function} got an unknown option '{key}' (options: {known})")
            if field_name in self.keyword:
                raise TypeError(f"{function} got {field_name} twice: as '{self.keyword[field_name]}'"
                                f" and as '{key}'")
            self.keyword[field_name] = key
            self.texts[field_name] = option_text(key, field, value)

    def keyword_for(self, field: str) -> str:
        return self.keyword.get(field, field)

    def items(self) -> list[tuple[str, str]]:
        return list(self.texts.items())
