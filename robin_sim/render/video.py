"""H.264 MP4 writing with PyAV (libx264, yuv420p) that survives an interrupted program.

The file is written at its final path as a *fragmented* MP4: an empty header first, then one
self-contained fragment per key frame (one key frame per second of video). Whatever stops the
program (Ctrl-C, an exception, even ``kill -9``), every fragment already written plays; a clean
:meth:`Mp4Writer.close` (also run by the context manager on ``KeyboardInterrupt``) flushes the
encoder and writes the last fragment. ffmpeg-based tools decode such files (the tests decode
them with PyAV); fragmented MP4 is also the layout browsers stream.
"""

from __future__ import annotations

import contextlib
import errno
import os
from fractions import Fraction
from pathlib import Path
from typing import Final

import av
import numpy as np
from av.container import OutputContainer

from pil.errors import RobinPilError, naming
from robin_sim.closing import ClosesOnExit
from robin_sim.render.mp4_trim import trim_torn_tail

CODEC: Final = "libx264"  # a literal: PyAV's types then know the stream is video
PIX_FMT = "yuv420p"
# empty_moov: header first; frag_keyframe: a fragment per key frame; default_base_moof: the
# layout browsers' media source extensions expect.
MOVFLAGS = "frag_keyframe+empty_moov+default_base_moof"


class VideoError(RobinPilError):
    """A video that cannot be written as asked (size, frame shape, closed writer)."""


class Mp4Writer(ClosesOnExit):
    """Write RGB frames (H, W, 3) uint8 to an H.264 MP4 at ``path`` as they come.

    ``width`` and ``height`` must be even (yuv420p halves the colour resolution). ``crf`` is
    x264's quality (lower is better, 23 its default); ``preset`` trades speed for size.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        width: int,
        height: int,
        fps: int = 30,
        crf: int = 23,
        preset: str = "veryfast",
    ) -> None:
        self.path = Path(path)
        if not self.path.parent.is_dir():
            raise VideoError(f"folder {str(self.path.parent)!r} of video {str(path)!r} not found")
        self.width = width
        self.height = height
        self.fps = int(fps)
        self.frames_written = 0
        self._failure: OSError | None = None  # the write error that stopped the video, if any
        self._container: OutputContainer | None = av.open(
            str(self.path),
            mode="w",
            format="mp4",
            options={"movflags": MOVFLAGS, "flush_packets": "1"},
        )
        stream = self._container.add_stream(CODEC, rate=self.fps)
        stream.width = width
        stream.height = height
        stream.pix_fmt = PIX_FMT
        stream.time_base = Fraction(1, self.fps)
        stream.codec_context.gop_size = self.fps  # a key frame, hence a fragment, each second
        stream.options = {"crf": str(crf), "preset": preset}
        self._stream = stream

    @property
    def closed(self) -> bool:
        """True once :meth:`close` has run."""
        return self._container is None

    def write(self, frame: np.ndarray) -> None:
        """Encode one frame; its shape must be (height, width, 3) and dtype uint8."""
        if self._container is None:
            if self._failure is not None:  # the disk filled up: say so again, not "closed"
                raise self._named(self._failure)
            raise VideoError(f"video {str(self.path)!r} is already closed")
        expected = (self.height, self.width, 3)
        if frame.shape != expected or frame.dtype != np.uint8:
            raise VideoError(
                f"frame must be a {expected} uint8 RGB array for video {str(self.path)!r}, "
                f"got {frame.shape} {frame.dtype}"
            )
        video_frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(frame), format="rgb24")
        video_frame.pts = self.frames_written
        try:
            self._container.mux(self._stream.encode(video_frame))
        except OSError as error:
            self._give_up(error)
            raise self._named(error) from error
        self.frames_written += 1

    def close(self) -> None:
        """Flush the encoder and finish the file; idempotent."""
        container, self._container = self._container, None
        if container is None:
            return
        try:
            try:
                container.mux(self._stream.encode(None))
            finally:
                container.close()
        except OSError as error:
            self._container = container
            self._give_up(error)
            raise self._named(error) from error

    def _named(self, error: OSError) -> OSError:
        """``error`` naming this video (FFmpeg's write errors name no file)."""
        return naming(OSError(error.errno, error.strerror), self.path)

    def _give_up(self, error: OSError) -> None:
        """After a failed write (a full disk): close without writing more and cut the file back
        to its last whole fragment, so that it decodes to its end; ``frames_written`` becomes
        the frames it still holds."""
        container, self._container = self._container, None
        self._failure = error
        if container is not None:
            with contextlib.suppress(Exception):
                container.close()
        if error.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG) and self.path.exists():
            trim_torn_tail(self.path)
            self.frames_written = count_frames(self.path)


def count_frames(path: str | os.PathLike[str]) -> int:
    """Video frames a file holds (packets read, nothing decoded); 0 if it does not open."""
    try:
        with av.open(str(path)) as container:
            return sum(1 for p in container.demux(container.streams.video[0]) if p.size)
    except (av.error.FFmpegError, IndexError, OSError):
        return 0


def probe_video(path: str | os.PathLike[str]) -> dict[str, object]:
    """Decode ``path`` and describe it: codec, pix_fmt, width, height, frames, fps, mean level.

    Used by the tests and the CLI to confirm a written video really plays.
    """
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        frames = 0
        level_sum = 0.0
        for frame in container.decode(stream):
            frames += 1
            level_sum += float(frame.to_ndarray(format="gray").mean())
        return {
            "codec": stream.codec_context.name,
            "pix_fmt": stream.codec_context.pix_fmt,
            "width": stream.codec_context.width,
            "height": stream.codec_context.height,
            "frames": frames,
            "fps": float(stream.average_rate or 0),
            "mean_level": level_sum / frames if frames else 0.0,
        }
