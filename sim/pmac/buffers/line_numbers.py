"""The host's numbering of rotary lines (``first_seq``): exactly-once delivery over retries.

This is a motionsim extension, not PMAC behaviour: a host that streams lines over REST numbers
each batch with ``first_seq`` (its own sequence number of ``lines[0]``), so a batch resent after a
lost reply is not stored twice. The rules (API.md, "first_seq"):

* the first numbered batch of a buffer (or after the numbering was reset) may start anywhere
  in ``0 .. MAX_SEQ``;
* afterwards the expected ``first_seq`` is ``last_seq + 1``. A batch may start earlier only when
  every line it repeats is *exactly* the text stored under that number: those lines are
  acknowledged again (idempotent), the rest stored. ``last_seq`` never goes backwards;
* a gap (``first_seq > last_seq + 1``), a repeated number with a different text, a repeat older
  than the texts kept (:data:`HISTORY`), or a number beyond :data:`MAX_SEQ` is refused
  (409 ``conflict`` with ``expected_seq`` and ``reason``) and nothing is stored;
* the numbering restarts (any ``first_seq`` accepted again) when the buffer is deleted
  (``DELETE ROT``), the controller reset, or the coordinate system aborted (``A``).

Lines stored without ``first_seq`` (and lines typed at the terminal) are not numbered and do not
move ``last_seq``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

from ...errors import Conflict

#: The highest line number accepted: the largest integer a JSON client (JavaScript) holds exactly.
MAX_SEQ = 2**53 - 1

#: Numbered line texts kept to recognise a resent batch (the newest ones).
HISTORY = 8192


class LineNumbering:
    """``last_seq`` and the texts of the newest numbered lines of one rotary buffer."""

    __slots__ = ("last_seq", "_texts")

    def __init__(self) -> None:
        #: The highest number stored (``None``: no numbered line since the numbering started).
        self.last_seq: int | None = None
        self._texts: deque[str] = deque(maxlen=HISTORY)  # texts of last_seq-len+1 .. last_seq

    @property
    def expected_seq(self) -> int | None:
        """The ``first_seq`` the next new batch must carry (``None``: any)."""
        return None if self.last_seq is None else self.last_seq + 1

    def reset(self) -> None:
        """Start the numbering again (``DELETE ROT``, reset, ``A``)."""
        self.last_seq = None
        self._texts.clear()

    def repeated(self, first_seq: int, texts: Sequence[str]) -> int:
        """How many leading lines of the batch were already stored; raises if it is refused.

        Raises:
            Conflict: a gap, a repeat that differs or is too old, or a number out of range;
                ``expected_seq`` and ``reason`` say which.
        """
        last_new = first_seq + len(texts) - 1
        if first_seq > MAX_SEQ or last_new > MAX_SEQ:
            self._refuse("out_of_range", first_seq,
                         f"line numbers {first_seq}..{last_new} are beyond {MAX_SEQ}")
        if self.last_seq is None:
            return 0
        expected = self.last_seq + 1
        if first_seq > expected:
            self._refuse("gap", first_seq, f"first_seq {first_seq} leaves a gap: lines "
                         f"{expected}..{first_seq - 1} were never stored")
        n_repeat = min(len(texts), expected - first_seq)
        oldest_kept = expected - len(self._texts)
        if n_repeat and first_seq < oldest_kept:
            self._refuse("overlap_too_old", first_seq,
                         f"first_seq {first_seq} repeats lines older than the {HISTORY} "
                         "newest numbered lines, which cannot be checked")
        for i in range(n_repeat):
            stored = self._texts[first_seq + i - oldest_kept]
            if texts[i] != stored:
                self._refuse("overlap_mismatch", first_seq,
                             f"line {first_seq + i} was stored as {stored!r}, not "
                             f"{texts[i]!r}", index=i)
        return n_repeat

    def record(self, first_seq: int, texts: Sequence[str], n_repeat: int) -> None:
        """The batch was stored: its new lines now carry their numbers."""
        new = texts[n_repeat:]
        if not new:
            return
        if self.last_seq is None:
            self._texts.clear()
        self._texts.extend(new)
        self.last_seq = first_seq + len(texts) - 1

    def _refuse(self, reason: str, first_seq: int, message: str, **details: object) -> None:
        expected = self.expected_seq
        hint = "any first_seq" if expected is None else f"first_seq {expected}"
        raise Conflict(f"{message}; nothing stored (expected {hint})", reason=reason,
                       first_seq=first_seq, expected_seq=expected, **details)


__all__ = ["HISTORY", "MAX_SEQ", "LineNumbering"]
