"""Exceptions raised by forcelayout.

Every error says what was wrong, where (a JSON path into the plan such as
``rules[4].target``) and, where it can, what to do about it.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Problem", "InputError", "PlanError", "UnknownRuleError", "MissingExtraError",
           "RuleOutputError"]


class InputError(Exception):
    """Marks an error in what the user gave (a file, a folder, an argument), not in the library.

    The command line shows such an error as one ``error:`` line and exits
    with status 2; other exceptions count as unexpected. Optional
    subpackages mark their input errors with it too (e.g.
    ``forcelayout.grounding.AssetLibraryError``).
    """


@dataclass(frozen=True)
class Problem:
    """One thing wrong with a plan.

    Attributes
    ----------
    path : str
        JSON path of the offending field, e.g. ``"objects[2].size"``.
    message : str
        What is wrong and, where possible, how to fix it.
    """

    path: str
    message: str

    def __str__(self) -> str:
        return f"{self.path}: {self.message}" if self.path else self.message


class PlanError(InputError, ValueError):
    """A plan that cannot be simulated; lists every problem found at once.

    Parameters
    ----------
    problems : list of Problem
        All problems found, each with the JSON path of its field.
    """

    def __init__(self, problems: list[Problem]):
        self.problems = list(problems)
        n = len(self.problems)
        if n == 1:  # one line
            super().__init__(f"the plan has 1 problem: {self.problems[0]}")
            return
        head = f"the plan has {n} problems:"
        super().__init__("\n".join([head, *(f"  - {p}" for p in self.problems)]))


class UnknownRuleError(LookupError):
    """A rule name that is not in the registry.

    The message suggests close matches and how to register a plugin.
    """

    def __str__(self) -> str:  # LookupError would quote the message like KeyError does not
        return str(self.args[0]) if self.args else ""


class MissingExtraError(ImportError):
    """An optional subpackage was imported without its pip extra installed."""


class RuleOutputError(ValueError):
    """A plugin rule's ``force()`` or ``satisfied()`` returned what no rule may return.

    Raised while sampling, naming the rule, what it returned and what it
    should return (``forcelayout.testing.check_rule`` checks a rule more
    thoroughly before any run).
    """
