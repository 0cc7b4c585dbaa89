"""Real signatures for the core's classes: inspect.signature (and so help(),
IDEs and notebooks' completion) cannot read a pybind11 constructor, but
pybind11 writes its signature, names, types and defaults, as the first line
of the constructor's docstring, which is parsed here once."""

import ast
import inspect


def give_signatures(*classes):
    """Sets each class's __signature__ from its pybind11 constructor's docstring."""
    for cls in classes:
        cls.__signature__ = constructor_signature(cls)


def constructor_signature(cls):
    """The signature of `cls(...)`: its pybind11 __init__'s, without self."""
    first_line = (cls.__init__.__doc__ or "").splitlines()[0]
    if not first_line.startswith("__init__("):
        raise ValueError(f"{cls.__name__}.__init__ has no pybind11 signature line: {first_line!r}")
    function = ast.parse(f"def {first_line}: pass").body[0]
    arguments = function.args
    defaults = [None] * (len(arguments.args) - len(arguments.defaults)) + arguments.defaults
    parameters = [
        inspect.Parameter(
            argument.arg,
            inspect.Parameter.POSITIONAL_OR_KEYWORD,
            default=inspect.Parameter.empty if default is None else ast.literal_eval(default),
            annotation=ast.unparse(argument.annotation) if argument.annotation else inspect.Parameter.empty,
        )
        for argument, default in zip(arguments.args, defaults)
    ][
        1:
    ]  # self
    return inspect.Signature(parameters)
