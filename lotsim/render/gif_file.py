"""An animated GIF written chunk by chunk (:func:`write_gif_chunks`), for the run's GIF of
:mod:`lotsim.render.animation`.

Each chunk of frames goes to imageio v3 as "P" frames with one fixed palette (no quantising
per frame) and comes back as a complete GIF in memory; the chunks' frame blocks are spliced
into one file (:func:`split_gif`), so memory does not grow with the length of the run. The
file is written under a temporary name and renamed.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence

import imageio.v3 as iio
import numpy as np

from lotsim.core.atomic import atomic_write


def _skip_sub_blocks(data: bytes, pos: int) -> int:
    while True:
        n = data[pos]
        pos += 1
        if n == 0:
            return pos
        pos += n


def split_gif(data: bytes) -> tuple[bytes, bytes, bytes]:
    """Cut a GIF into (screen: logical screen descriptor and global colour table,
    preamble: the extensions before the first frame, frames: every frame's blocks,
    without the trailer)."""
    if data[:6] not in (b"GIF87a", b"GIF89a"):
        raise ValueError("not a GIF")
    flags = data[10]
    pos = 13 + (3 * 2 ** ((flags & 7) + 1) if flags & 0x80 else 0)
    screen_end = pos
    first = None
    while True:
        tag = data[pos]
        if tag == 0x3B:  # trailer
            break
        if tag == 0x21:  # extension: label, then sub-blocks
            label = data[pos + 1]
            if first is None and label == 0xF9:
                first = pos
            pos = _skip_sub_blocks(data, pos + 2)
        elif tag == 0x2C:  # image: descriptor, local table, LZW code size, sub-blocks
            if first is None:
                first = pos
            fl = data[pos + 9]
            pos += 10 + (3 * 2 ** ((fl & 7) + 1) if fl & 0x80 else 0)
            pos = _skip_sub_blocks(data, pos + 1)
        else:
            raise ValueError(f"unexpected GIF block 0x{tag:02x} at byte {pos}")
    if first is None:
        first = pos
    return data[6:screen_end], data[screen_end:first], data[first:pos]


def write_gif_chunks(path: str | os.PathLike,
                     chunks: Iterable[tuple[np.ndarray, Sequence[int]]],
                     palette: bytes) -> None:
    """Write the frames of ``chunks`` as one animated GIF at ``path`` that loops for ever.

    Each chunk is ``(frames, durations)``: frames as palette indices, shaped (K, height,
    width), and the display time of each [ms]; ``palette`` is the RGB bytes every frame is
    drawn in. The next chunk is asked for once the last one is in the file. Nothing is left
    at ``path`` or beside it if this fails or is interrupted (``chunks`` raising too).
    """
    with atomic_write(path) as fh:
        screen = None
        for frames, durations in chunks:
            # one frame takes one duration, not a list (Pillow 13 writes a lone frame as a
            # still image and refuses a list)
            duration = durations if len(frames) > 1 else durations[0]
            data = iio.imwrite("<bytes>", frames, extension=".gif", mode="P",
                               palette=palette, loop=0, duration=duration)
            scr, pre, body = split_gif(data)
            if screen is None:
                screen = scr
                fh.write(data[:6] + scr + pre)
            elif scr != screen:
                raise RuntimeError("GIF chunks came out with different colour tables")
            fh.write(body)
        fh.write(b";")
