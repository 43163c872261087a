"""Checks of Python-side arguments: the wrong type is a TypeError, a value
out of range a ValueError, each naming the argument and the value given
(nothing is converted silently: bool("False") is True, int(2.7) is 2)."""

import numbers
import operator


def _is_numpy_bool(value):
    t = type(value)
    return t.__module__ == "numpy" and t.__name__ in ("bool_", "bool")


def as_bool(name, value):
    """``value`` if it is a bool (or a numpy bool), else TypeError."""
    if isinstance(value, bool) or _is_numpy_bool(value):
        return bool(value)
    raise TypeError("{} must be a bool, got {!r}".format(name, value))


def as_real(name, value):
    """float(value) for a real number (int, float, numpy numbers, not bool
    or str), else TypeError; an integer no float holds (10 ** 400) is an
    OverflowError naming it."""
    if isinstance(value, bool) or _is_numpy_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError("{} must be a real number, got {!r}".format(name, value))
    try:
        return float(value)
    except OverflowError:
        raise OverflowError("{} is too large for a floating-point number, got {!r}".format(
            name, value)) from None


def as_int(name, value, lo, hi):
    """An integer (int, numpy integer; not bool or float) in lo..hi: else
    TypeError or ValueError."""
    if isinstance(value, bool) or _is_numpy_bool(value):
        raise TypeError("{} must be an integer, got {!r}".format(name, value))
    try:
        v = operator.index(value)
    except TypeError:
        raise TypeError("{} must be an integer, got {!r}".format(name, value)) from None
    if not lo <= v <= hi:
        raise ValueError("{} must be {}..{}, got {}".format(name, lo, hi, v))
    return v
