"""The GIF's frames as an H.264 video (``lotsim render --mp4``).

The frames are those of :mod:`lotsim.render.animation` (same times, same drawing, the
same ``skip_quiet``), turned from palette indices into RGB and handed to ffmpeg at a
constant ``fps``: frame ``k`` shows run time ``FramePlan.times[k]`` from ``k / fps`` s
of the video on. ffmpeg comes from the optional ``imageio-ffmpeg`` package (its wheel
carries its own binary): ``pip install 'lotsim[video]'``. The video is written under a
temporary name beside the target and renamed when it is complete.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lotsim.errors import LotsimError, SettingsError
from lotsim.render.animation import GifRenderer, plan_frames
from lotsim.scenario import GifSettings

CRF = 16
"""x264's constant rate factor: 0 lossless, 23 its default; 16 keeps the thin lines and
small text of a frame within a few levels of the GIF."""


class VideoUnavailable(LotsimError):
    """ffmpeg is not installed (the ``video`` extra: ``imageio-ffmpeg``)."""


def require_ffmpeg():  # the imageio_ffmpeg module
    """The :mod:`imageio_ffmpeg` module, or :class:`VideoUnavailable` naming the extra."""
    try:
        import imageio_ffmpeg
    except ImportError:
        raise VideoUnavailable("an MP4 video needs ffmpeg from the imageio-ffmpeg package: "
                               "pip install 'lotsim[video]'") from None
    return imageio_ffmpeg


@dataclass(frozen=True)
class VideoInfo:
    """What :func:`write_mp4` wrote."""

    path: Path
    frames: int
    duration: float
    """Length of the video [s]."""
    speed: float
    start: float
    end: float
    skipped: float
    """Run time left out (``skip_quiet``) [s]."""
    bytes: int


def write_mp4(doc: dict, path: str | os.PathLike, settings: GifSettings | None = None, *,
              progress: Callable[[int, int], None] | None = None) -> VideoInfo:
    """Render the run in ``doc`` (a result document) as an H.264 MP4 video at ``path``.

    Raises
    ------
    VideoUnavailable
        Without the ``imageio-ffmpeg`` package.
    SettingsError
        An odd width or height (H.264's 4:2:0 colour needs even ones), or a span outside
        the run.
    ReplayError, LotFormatError
        When ``doc`` is not a result that can be drawn.
    """
    settings = settings or GifSettings()
    w, h = settings.size
    if w % 2 or h % 2:
        raise SettingsError("size", f"an H.264 video needs an even width and height, found "
                                    f"{w}x{h}")
    ffmpeg = require_ffmpeg()
    renderer = GifRenderer(doc, settings)
    plan = plan_frames(renderer.replay, settings)
    palette = np.asarray(renderer.rgb + [(0, 0, 0)] * (256 - len(renderer.rgb)),
                         dtype=np.uint8)
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".mp4", dir=target.parent)
    os.close(fd)
    n = len(plan.times)
    try:
        writer = ffmpeg.write_frames(
            tmp, (w, h), fps=settings.fps, codec="libx264", pix_fmt_in="rgb24",
            pix_fmt_out="yuv420p", quality=None, macro_block_size=1,
            output_params=["-crf", str(CRF), "-preset", "medium", "-movflags", "+faststart"],
            ffmpeg_log_level="error")
        writer.send(None)  # start ffmpeg
        try:
            for _, b, frames in renderer.chunks(plan):
                for frame in frames:
                    writer.send(np.ascontiguousarray(palette[frame]))
                if progress is not None:
                    progress(b, n)
        finally:
            writer.close()
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    return VideoInfo(target, n, n / settings.fps, plan.speed, plan.start, plan.end,
                     sum(b - a for a, b in plan.skips), target.stat().st_size)
