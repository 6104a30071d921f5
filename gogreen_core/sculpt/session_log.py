"""The log of a sculptor's operations in memory (typed records, in order) and who listens to it
(the crash-recovery journal)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, cast

from gogreen_core.sculpt.operations import Operation

__all__ = ["LogListener", "SessionLog"]


#: ``listener(kind, item, length)`` of a :class:`SessionLog`: ``kind`` is ``"append"`` or
#: ``"replace"`` (``item`` the operation now last), ``"truncate"`` (``item`` None) or ``"event"``
#: (``item`` a mouse event of the stroke in progress, not yet an operation); ``length`` is the
#: number of operations after the change.
LogListener = Callable[[str, object, int], None]


class SessionLog:
    """The operations a sculptor did, in order, and who listens to them."""

    def __init__(self) -> None:
        self._operations: list[Operation] = []
        self._listeners: list[LogListener] = []

    def subscribe(self, listener: LogListener) -> Callable[[], None]:
        """Call ``listener`` after every change (see :data:`LogListener`); returns the function
        that unsubscribes it."""
        self._listeners.append(listener)
        return lambda: self._listeners.remove(listener) if listener in self._listeners else None

    def _notify(self, kind: str, item: object) -> None:
        for listener in self._listeners:
            listener(kind, item, len(self._operations))

    def event(self, event: object) -> None:
        """Tell the listeners about a mouse event of the stroke in progress (it becomes part of
        the stroke's operation when the stroke ends)."""
        self._notify("event", event)

    def __len__(self) -> int:
        return len(self._operations)

    def __iter__(self) -> Iterator[Operation]:
        return iter(self._operations)

    def record(self, operation: Operation, replace_last: bool = False) -> None:
        """Append ``operation``; with ``replace_last`` it replaces the last one of the same type
        (a slider drag collapses into its last value), keeping that one's ``continued`` flag."""
        last = self._operations[-1] if self._operations else None
        if replace_last and type(last) is type(operation):
            flag = getattr(last, "continued", None)
            if flag is not None and flag != cast(Any, operation).continued:  # (same type)
                operation = type(operation)(**{**operation.__dict__, "continued": flag})
            self._operations[-1] = operation
            self._notify("replace", operation)
        else:
            self._operations.append(operation)
            self._notify("append", operation)

    def truncate(self, length: int) -> None:
        """Forget the operations after the first ``length`` (a rolled-back replay)."""
        if length < len(self._operations):
            del self._operations[length:]
            self._notify("truncate", None)
