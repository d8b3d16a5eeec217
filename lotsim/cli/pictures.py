"""Writing a run's animated GIF, interactive replay and video, each with its one-line
report: shared by ``lotsim run`` (beside result.json) and ``lotsim render``."""

from __future__ import annotations

import gc
import sys

from lotsim import api
from lotsim.cli.output import EXIT_OK, bad, cannot_write, option, plural
from lotsim.cli.progress import ProgressBar, noting_sigint
from lotsim.errors import ReplayError, SettingsError


def save_gif(doc: dict, path, settings) -> int:
    """Draw the run ``doc`` as an animated GIF; the exit code."""
    bar = ProgressBar("rendering frames")
    seen: list[bool] = []
    hook = sys.unraisablehook
    error, interrupted = None, False
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
        bar.close()
    if interrupted:
        gc.collect()
        sys.unraisablehook = hook
        raise KeyboardInterrupt
    if isinstance(error, (ReplayError, api.LotFormatError)):
        return bad(f"cannot draw this result: {error}")
    if isinstance(error, SettingsError):  # the asked span is outside the run
        return bad(f"{option(error.name)}: {error.message}")
    if isinstance(error, ValueError):
        return bad(str(error))
    if isinstance(error, OSError):
        return cannot_write(path, error)
    faster = (f" (sped up from {settings.speed:g}× to fit {info.frames} frames)"
              if info.speed > settings.speed * (1 + 1e-9) else "")
    print(f"  wrote {info.path}: {info.frames} frames, {info.duration:.1f} s at "
          f"{info.speed:.3g}× run time{faster}, {info.start:.1f}–{info.end:.1f} s of the run, "
          f"{info.bytes / 1e6:.1f} MB")
    return EXIT_OK


def save_html(doc: dict, path, settings) -> int:
    """Write the run ``doc`` as an interactive replay; the exit code."""
    try:
        info = api.render_html(doc, path, settings)
    except (ReplayError, api.LotFormatError) as exc:
        return bad(f"cannot draw this result: {exc}")
    except OSError as exc:
        return cannot_write(path, exc)
    print(f"  wrote {info.path}: replay of {plural(info.vehicles, 'vehicle')}, "
          f"{info.kept} of {info.samples} samples kept (within "
          f"{(settings.tolerance if settings else 0.01) * 100:g} cm), "
          f"{info.bytes / 1e6:.2f} MB")
    return EXIT_OK


def save_mp4(doc: dict, path, settings) -> int:
    """Encode the run ``doc`` as an H.264 video; the exit code."""
    bar = ProgressBar("encoding video")
    try:
        info = api.render_mp4(doc, path, settings, progress=bar)
    except (ReplayError, api.LotFormatError) as exc:
        return bad(f"cannot draw this result: {exc}")
    except api.VideoUnavailable as exc:
        return bad(f"--mp4: {exc}")
    except SettingsError as exc:
        return bad(f"{option(exc.name)}: {exc.message}")
    except OSError as exc:
        return cannot_write(path, exc)
    finally:
        bar.close()
    skipped = f", {info.skipped:.0f} s of quiet run time skipped" if info.skipped else ""
    print(f"  wrote {info.path}: {info.frames} frames, {info.duration:.1f} s at "
          f"{info.speed:.3g}× run time, {info.start:.1f}–{info.end:.1f} s of the run"
          f"{skipped}, {info.bytes / 1e6:.1f} MB")
    return EXIT_OK

