"""Errors are values with a place. The CLI turns each into one line and an exit code."""
from __future__ import annotations


class HncError(Exception):
    """Base of every error the user can cause; exit code 2 (bad input)."""

    exit_code = 2

    def one_line(self) -> str:
        return f"error: {self}"


class NCError(HncError):
    """An alarm of the interpreter: where (file, 1-based line and column), the block, why."""

    def __init__(self, message: str, line: int = 0, col: int = 0, block: str = "",
                 file: str = "<program>"):
        super().__init__(message)
        self.message = message
        self.line = line
        self.col = col
        self.block = block
        self.file = file

    def one_line(self) -> str:
        head = f"{self.file}:{self.line}:{self.col}: alarm: {self.message}"
        if self.block:
            head += f"  [{self.block.strip()}]"
        return head


class ProfileError(HncError):
    """The CAD part is not a turned part we can profile (says what and where)."""


class StockError(HncError):
    """A stock specification that cannot be parsed or does not fit the part."""


class ToolError(HncError):
    """A tool, insert code, tool library or machine file that is wrong."""


class PlanError(HncError):
    """The planner refuses: the part cannot be made from this stock with these tools."""


class PartError(HncError):
    """A part file or its parameters are wrong (unknown parameter, not a number, ...)."""
