"""A long render's progress on stderr (``mechgen animate``): once the first frames say how
long the film will take, and only when that is more than a few seconds, the estimate,
then a line at every tenth of the frames with the time left."""
from __future__ import annotations

import sys
import time

QUIET_SECONDS = 5.0     # a film estimated to take less says nothing
FIRST_FRAMES = 3        # frames timed before the estimate (the first draws the still parts)


class RenderProgress:
    """``progress(done, total)`` for Animation.save: silent for a quick film; for a long
    one "rendering N frames: about S s", then "frame k/N (p %), about S s left"."""

    def __init__(self, what="film", stream=None, clock=time.monotonic):
        self.what, self.stream, self.clock = what, stream, clock
        self.start = clock()
        self.talking = False
        self.next_tenth = 1

    def _say(self, text):
        stream = self.stream if self.stream is not None else sys.stderr
        print(f"mechgen: {text}", file=stream, flush=True)

    def __call__(self, done, total):
        elapsed = self.clock() - self.start
        if done < min(FIRST_FRAMES, total) or total <= 0:
            return
        rate = done / elapsed if elapsed > 0 else float("inf")
        left = (total - done) / rate if rate > 0 else float("inf")
        if not self.talking:
            if elapsed + left < QUIET_SECONDS or done == total:
                return
            self.talking = True
            self._say(f"rendering {total} frames of the {self.what}: about "
                      f"{elapsed + left:.0f} s ({rate:.3g} frames a second; fewer frames "
                      "(-n) or a smaller --dpi render sooner)")
            self.next_tenth = int(10 * done / total) + 1
            return
        if done == total:
            self._say(f"rendered {total} frames in {elapsed:.0f} s; writing the file")
            return
        if 10 * done >= self.next_tenth * total:
            self.next_tenth = int(10 * done / total) + 1
            self._say(f"frame {done}/{total} ({100 * done // total} %), about {left:.0f} s "
                      "left")
