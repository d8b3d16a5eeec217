"""``lotsim render``: draw a result.json as an animated GIF, an interactive HTML replay, an
MP4 video and/or a timeline plot."""

from __future__ import annotations

import argparse
import os

from lotsim import api
from lotsim.cli.output import (
    EXIT_OK,
    bad,
    cannot_write,
    given,
    name_problem,
    option,
    picture_size,
    sizes,
)
from lotsim.cli.pictures import save_gif, save_html, save_mp4
from lotsim.errors import ReplayError, ResultFormatError, SettingsError

HELP = ("draw a result.json: animated GIF, interactive HTML replay, MP4 video, timeline "
        "plot")
EXITS = "0 written; 2 bad input, or a result that cannot be drawn"


def add_arguments(rd: argparse.ArgumentParser) -> None:
    rd.add_argument("result", metavar="RESULT_JSON", help="a result.json of lotsim run")
    rd.add_argument("--gif", metavar="GIF", help="animated GIF to write")
    rd.add_argument("--html", metavar="HTML", help="interactive replay to write: one "
                    "self-contained HTML file that opens from disk in a browser")
    rd.add_argument("--mp4", metavar="MP4", help="the GIF's frames as an H.264 video (needs "
                    "pip install 'lotsim[video]'; even --size)")
    rd.add_argument("--timeline", metavar="PNG", help="timeline plot to write (matplotlib)")
    gs = api.GifSettings()
    # defaults None: an option given where it would change nothing is refused, not ignored
    rd.add_argument("--fps", type=float, help=f"GIF and MP4 frames per second ({gs.fps:g})")
    rd.add_argument("--speed", type=float,
                    help=f"GIF and MP4: run seconds per second of film ({gs.speed:g}); the "
                    f"replay opens at this speed, one of "
                    f"{', '.join(map(str, api.REPLAY_SPEEDS))} "
                    f"({api.HtmlSettings().speed:g})")
    size = "x".join(map(str, gs.size))
    rd.add_argument("--size", help=f"GIF and MP4 size WxH in pixels, {sizes()} ({size})")
    rd.add_argument("--from", dest="start", type=float, help="GIF and MP4: first run time "
                    "shown [s] (default the first arrival)")
    rd.add_argument("--to", dest="end", type=float, help="GIF and MP4: last run time shown "
                    "[s] (default the last event)")
    rd.add_argument("--max-frames", type=int,
                    help=f"GIF and MP4: at most this many frames; a longer span plays faster "
                    f"({gs.max_frames})")
    rd.add_argument("--trail", type=float,
                    help=f"GIF and MP4: seconds of path drawn behind a moving car "
                    f"({gs.trail:g})")
    rd.add_argument("--skip-quiet", action="store_true", default=None,
                    help="GIF and MP4: leave out stretches in which no car moves (the frame "
                    "says how long was skipped); the replay's toggle starts on either way")
    rd.add_argument("--no-legend", dest="legend", action="store_const", const=False,
                    help="GIF and MP4: no key of the cars' colours in the footer")
    rd.add_argument("--view", choices=api.VIEWS,
                    help=f"GIF and MP4: frame the ground the cars use, or the whole lot "
                    f"({gs.view})")


FILM_OPTIONS = (("--fps", "fps"), ("--size", "size"), ("--from", "start"), ("--to", "end"),
                ("--max-frames", "max_frames"), ("--trail", "trail"),
                ("--no-legend", "legend"), ("--view", "view"))
"""Options that only set the GIF's and the video's frames."""


def _pointless(args: argparse.Namespace) -> str | None:
    """An option that would change nothing for the files asked for, refused."""
    film = args.gif or args.mp4
    if not film:
        for opt, name in FILM_OPTIONS + (("--skip-quiet", "skip_quiet"),):
            if getattr(args, name) is not None:
                asked = " and ".join(o for o, path in (("--html", args.html),
                                                       ("--timeline", args.timeline)) if path)
                return (f"{opt}: only --gif and --mp4 have frames; for {asked} it would "
                        f"change nothing")
        if args.speed is not None and not args.html:
            return "--speed: the timeline has no speed; it would change nothing"
    if args.html and args.speed is not None and args.speed not in api.REPLAY_SPEEDS:
        return (f"--speed: the replay opens at one of "
                f"{', '.join(map(str, api.REPLAY_SPEEDS))}, found {args.speed:g}")
    return None


def execute(args: argparse.Namespace) -> int:
    if not (args.gif or args.html or args.mp4 or args.timeline):
        return bad("render: nothing to do: give --gif GIF, --html HTML, --mp4 MP4 and/or "
                   "--timeline PNG")
    pointless = _pointless(args)
    if pointless:
        return bad(pointless)
    gs = api.GifSettings()
    size = picture_size(args.size) if args.size is not None else gs.size
    if isinstance(size, str):
        return bad(size)
    try:
        settings = api.GifSettings(
            fps=gs.fps if args.fps is None else args.fps,
            speed=gs.speed if args.speed is None else args.speed, size=size,
            start=args.start, end=args.end,
            max_frames=gs.max_frames if args.max_frames is None else args.max_frames,
            trail=gs.trail if args.trail is None else args.trail,
            skip_quiet=bool(args.skip_quiet), legend=args.legend is None,
            view=gs.view if args.view is None else args.view)
        html = None
        if args.html:  # the replay opens at --speed (checked above to be one it offers)
            html = api.HtmlSettings(**({} if args.speed is None else
                                       {"speed": int(args.speed) if args.speed.is_integer()
                                        else args.speed}))
    except SettingsError as exc:
        return bad(f"{option(exc.name)}: {exc.message}")
    problem = _outputs_problem(args, size)
    if problem:
        return bad(problem)
    try:
        doc = api.load_result(args.result, packed=True)
    except ResultFormatError as exc:
        return bad(str(exc))
    if not isinstance(doc.get("lot"), dict) or "drawing" not in doc["lot"]:
        return bad(f"{args.result}: no lot.drawing: written by an older lotsim? run the "
                   "scenario again")
    said = []
    with api.OutputSet() as outputs:  # checked before drawing, written whole or not at all
        for opt, path, write, these in (("--gif", args.gif, save_gif, settings),
                                        ("--html", args.html, save_html, html),
                                        ("--mp4", args.mp4, save_mp4, settings),
                                        ("--timeline", args.timeline, _timeline, None)):
            if path:
                staged = outputs.file(path, name=given(opt, path))
                code, line = write(doc, staged, these, shown=path)
                if code != EXIT_OK:
                    return code
                said.append(line)
        outputs.commit()
    print("\n".join(said))
    return EXIT_OK


def _outputs_problem(args: argparse.Namespace, size: tuple[int, int]) -> str | None:
    """What is wrong with the files to write (names, folders, one file named twice, a
    video that cannot be made), before the result is read; None if nothing."""
    outputs = (("--gif", args.gif, ".gif"), ("--html", args.html, ".html"),
               ("--mp4", args.mp4, ".mp4"), ("--timeline", args.timeline, ".png"))
    for opt, path, suffix in outputs:
        problem = path and name_problem(opt, path, suffix)
        if problem:
            return problem
    given = [path for _, path, _ in outputs if path]
    if len({os.path.realpath(p) for p in given}) < len(given):
        return "render: two outputs name the same file"
    if args.mp4 and (size[0] % 2 or size[1] % 2):
        return (f"--size: an H.264 video needs an even width and height, found "
                f"{size[0]}x{size[1]}")
    if args.mp4:
        try:
            api.require_ffmpeg()
        except api.VideoUnavailable as exc:
            return f"--mp4: {exc}"
    return None


def _timeline(doc: dict, path, _settings=None, *, shown: str) -> tuple[int, str | None]:
    try:
        api.plot_timeline(doc, path)
    except ImportError:
        return bad("--timeline needs matplotlib: pip install 'lotsim[plot]'"), None
    except ReplayError as exc:
        return bad(f"cannot draw this result: {exc}"), None
    except OSError as exc:
        return cannot_write(shown, exc), None
    return EXIT_OK, f"  wrote {shown}"
