"""The one exception type that reaches the user as a message, not a traceback."""


class UserError(Exception):
    """Input the user can fix: a bad argument, a missing file, no Vulkan driver.

    The CLI prints ``str(err)`` on one line of stderr and exits with code 2.
    The message says what was wrong and how to fix it.
    """
