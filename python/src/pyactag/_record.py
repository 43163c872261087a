"""Value objects whose fields are their ``__slots__`` (Detection, Pose,
Track): pickling with every protocol and equality field by field, once."""


class SlotRecord:
    """Base of a value object: ``__slots__`` lists its fields in the order
    its constructor takes them."""

    __slots__ = ()

    def __reduce__(self):
        """Pickling with every protocol (``__slots__`` alone needs 2+)."""
        return (type(self), tuple(getattr(self, k) for k in self.__slots__))

    def __eq__(self, other):
        if not (isinstance(other, type(self)) or isinstance(self, type(other))):
            return NotImplemented
        return all(getattr(self, k) == getattr(other, k) for k in self.__slots__)

    __hash__ = None  # mutable fields: not hashable, as any class with __eq__
