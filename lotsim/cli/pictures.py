"""Writing a run's animated GIF, interactive replay and video, each with its one-line
report: shared by ``lotsim run`` (beside result.json) and ``lotsim render``.

Each writes to ``path`` (a staged file of the command's
:class:`~lotsim.core.atomic.OutputSet`) and speaks of ``shown`` (the file as the user named
it); it returns its exit code and, written, the line that reports it, for the command to
print once the whole set is in place."""

from __future__ import annotations

import gc
import sys

from lotsim import api
from lotsim.cli.output import EXIT_OK, bad, cannot_write, option, plural
from lotsim.cli.progress import ProgressBar, noting_sigint
from lotsim.errors import ReplayError, SettingsError

Saved = tuple[int, str | None]
"""An exit code and, when it is 0, the line reporting the file written."""


def save_gif(doc: dict, path, settings, *, shown=None) -> Saved:
    """Draw the run ``doc`` as an animated GIF."""
    bar = ProgressBar("rendering frames")
    seen: list[bool] = []
    hook = sys.unraisablehook
    error, interrupted, info = None, False, None
    try:
        with noting_sigint(seen):
            info = api.render_gif(doc, path, settings, progress=bar)
    except (KeyboardInterrupt, ReplayError, api.LotFormatError, ValueError, OSError) as exc:
        interrupted = bool(seen) or isinstance(exc, KeyboardInterrupt)
        if interrupted:
            # Ctrl-C, which Pillow may turn into an error of its own; the half-made writer
            # complains as it is collected (when this block lets go of it): not for the
            # user's eyes
            sys.unraisablehook = lambda _: None
        else:
            error = exc
    finally:
        bar.close("done" if info is not None else "interrupted" if interrupted else "stopped")
    if interrupted:
        gc.collect()
        sys.unraisablehook = hook
        raise KeyboardInterrupt
    shown = path if shown is None else shown
    if isinstance(error, (ReplayError, api.LotFormatError)):
        return bad(f"cannot draw this result: {error}"), None
    if isinstance(error, SettingsError):  # the asked span is outside the run
        return bad(f"{option(error.name)}: {error.message}"), None
    if isinstance(error, ValueError):
        return bad(str(error)), None
    if isinstance(error, OSError):
        return cannot_write(shown, error), None
    faster = (f" (sped up from {settings.speed:g}× to fit {info.frames} frames)"
              if info.speed > settings.speed * (1 + 1e-9) else "")
    skipped = f", {info.skipped:.0f} s of quiet run time skipped" if info.skipped else ""
    return EXIT_OK, (f"  wrote {shown}: {info.frames} frames, {info.duration:.1f} s at "
                     f"{info.speed:.3g}× run time{faster}, {info.start:.1f}–{info.end:.1f} s "
                     f"of the run{skipped}, {info.bytes / 1e6:.1f} MB")


def save_html(doc: dict, path, settings, *, shown=None) -> Saved:
    """Write the run ``doc`` as an interactive replay."""
    shown = path if shown is None else shown
    try:
        info = api.render_html(doc, path, settings)
    except (ReplayError, api.LotFormatError) as exc:
        return bad(f"cannot draw this result: {exc}"), None
    except OSError as exc:
        return cannot_write(shown, exc), None
    return EXIT_OK, (f"  wrote {shown}: replay of {plural(info.vehicles, 'vehicle')}, "
                     f"{info.kept} of {info.samples} samples kept (within "
                     f"{(settings.tolerance if settings else 0.01) * 100:g} cm), "
                     f"{info.bytes / 1e6:.2f} MB")


def save_mp4(doc: dict, path, settings, *, shown=None) -> Saved:
    """Encode the run ``doc`` as an H.264 video."""
    shown = path if shown is None else shown
    try:
        with ProgressBar("encoding video") as bar:
            info = api.render_mp4(doc, path, settings, progress=bar)
    except (ReplayError, api.LotFormatError) as exc:
        return bad(f"cannot draw this result: {exc}"), None
    except api.VideoUnavailable as exc:
        return bad(f"--mp4: {exc}"), None
    except SettingsError as exc:
        return bad(f"{option(exc.name)}: {exc.message}"), None
    except OSError as exc:
        return cannot_write(shown, exc), None
    skipped = f", {info.skipped:.0f} s of quiet run time skipped" if info.skipped else ""
    return EXIT_OK, (f"  wrote {shown}: {info.frames} frames, {info.duration:.1f} s at "
                     f"{info.speed:.3g}× run time, {info.start:.1f}–{info.end:.1f} s of the "
                     f"run{skipped}, {info.bytes / 1e6:.1f} MB")

