"""shaderfit.Error: the library's error, located (a field, a keyword, a formula's line and column)."""

from __future__ import annotations


class Error(ValueError):
    """A bad input, as the library reports it.

    ``message`` says what is wrong; ``source`` where (a keyword such as ``"max_power"``, a
    formula, ``"X"``); ``line`` and ``column`` are 1-based within it, 0 when not known.
    ``str(error)`` is ``"source:line:column: message"`` without the parts that are not known.
    """

    def __init__(self, message: str, source: str = "", line: int = 0, column: int = 0):
        self.message = message
        self.source = source
        self.line = line
        self.column = column
        super().__init__(self._text())

    def _text(self) -> str:
        where = self.source
        if where and self.line:
            where += f":{self.line}"
            if self.column:
                where += f":{self.column}"
        return f"{where}: {self.message}" if where else self.message

    def __reduce__(self):  # picklable, as exceptions crossing processes must be
        return (type(self), (self.message, self.source, self.line, self.column))


_FIELD_PREFIX = "SearchOptions::"


def renamed(error: Error, keyword_for_field) -> Error:
    """The error with a search option's location ("SearchOptions::time_limit_s") written as the
    keyword the caller used for it ("time")."""
    if not error.source.startswith(_FIELD_PREFIX):
        return error
    field = error.source[len(_FIELD_PREFIX):]
    return Error(error.message, keyword_for_field(field), error.line, error.column)
