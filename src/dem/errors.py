"""The one exception type for bad user input.

Every message is one line: the offending field (dotted path into the scene or case file),
what is wrong with it, and how to fix it. The command-line driver prints it and exits 2.
"""


class InputError(ValueError):
    """Bad input: ``field`` names where, ``problem`` says what, ``fix`` says how to mend it."""

    def __init__(self, field: str, problem: str, fix: str = ""):
        self.field = field
        self.problem = problem
        self.fix = fix
        message = f"{field}: {problem}"
        if fix:
            message += f"; {fix}"
        super().__init__(message)
