"""Python signatures for the compiled functions of reproject._reproject.

pybind11's functions carry no Python signature: inspect.signature fails on them, and help() and
editors cannot show their parameters. Each public function of the package is therefore declared
in Python, with the compiled function's parameters, defaults and documentation
(tests/python/test_package.py checks that the parameters match, and that the stubs match both).
A call is passed on to the compiled function as it was made, so that the function's own checks
answer a wrong one: its TypeError names the argument at fault and what it takes, and suggests
the nearest keyword for a misspelt one, which Python's own binding of a def would not.
"""
import functools


def forwards_to(compiled):
    """Decorator: the declared def becomes the face of `compiled` (its name, signature through
    __wrapped__, docstring); calling it calls `compiled` with the same arguments."""

    def declare(declared):
        @functools.wraps(declared)
        def call(*args, **kwargs):
            return compiled(*args, **kwargs)

        call.__compiled__ = compiled
        return call

    return declare
