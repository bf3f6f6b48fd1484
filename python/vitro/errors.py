"""The exceptions of the vitro package.

Every error the Rust side reports is a :class:`VitroError`: bad input (a malformed
scenario or experiment, a value out of range) is an :class:`InputError`, which is also a
:class:`ValueError`; a failure while setting up or running is a :class:`RunError`, also a
:class:`RuntimeError`. The messages are those of the ``vitro`` command (file, line and
column of a problem in a file). A bug inside vitro surfaces as a ``RunError`` whose message
starts with ``internal error``, never as a crash.
"""


class VitroError(Exception):
    """Any error reported by vitro."""


class InputError(VitroError, ValueError):
    """Bad input: the ``vitro`` command exits with code 2 on it."""


class RunError(VitroError, RuntimeError):
    """A failure while setting up or running: the ``vitro`` command exits with code 1."""
