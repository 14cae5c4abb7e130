"""python3 -m reproject convert | scene-video: whole sequences and videos (docs/CLI.md "convert").

The flags are the C++ tool's warp and pair flags, with the same names, defaults and meanings, plus
the outputs, segments and workers of reproject.video.convert. Errors are one line on stderr,
"reproject: error: ...", with the C++ tool's exit codes (docs/CLI.md "Exit codes and messages"): 2
for a usage error, 3 for an input, 4 for an output, 1 for the rest; a run that SIGINT, SIGTERM,
SIGHUP or SIGQUIT stops cleans up and then dies of that signal, as the C++ tool does.
"""
import argparse
import os
import signal
import sys

from . import video


def _number(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a decimal number") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"'{text}' is not a finite number")
    return value


def _convert_parser(commands):
    p = commands.add_parser("convert", help="colour + depth sequences or videos -> a stereo video or sequence",
                            description="Converts a whole sequence or video (reproject.video.convert).")
    io = p.add_argument_group("inputs and outputs")
    io.add_argument("--color", required=True, metavar="SRC", help="colour: a video, a pattern (f/%%04d.png) or a folder")
    io.add_argument("--depth", required=True, metavar="SRC", help="depth: a grey video, a pattern or a folder (one channel)")
    io.add_argument("--out", required=True, metavar="OUT", help="a video (.mkv, .mp4, ...) or a pattern (out/%%04d.png)")
    io.add_argument("--layout", default="sbsl", metavar="NAME", help=f"{', '.join(video.layouts)} [sbsl]")
    io.add_argument("--suffix", action="store_true", help="add the players' layout suffix to the output name")
    io.add_argument("--codec", metavar="NAME", help="libx264, libx265 or ffv1 [libx264]")
    io.add_argument("--pixel-format", metavar="FMT", help="the output's pixel format [the input's, or yuv420p(10le)]")
    io.add_argument("--crf", type=int, metavar="N", help="x264/x265 quality [18 / 20]")
    io.add_argument("--fps", type=_number, metavar="R", help="frame rate of image sequences [25]")
    cam = p.add_argument_group("the camera (as warp and pair)")
    cam.add_argument("--encoding", metavar="NAME", help="linear, standard, gl_ndc, reversed, reversed_infinite, "
                                                        "infinite, disparity")
    cam.add_argument("--near", type=_number, metavar="Z")
    cam.add_argument("--far", type=_number, metavar="Z")
    cam.add_argument("--depth-scale", type=_number, metavar="K", help="stored values times K [1]")
    cam.add_argument("--unknown-depth", metavar="V", help="stored value meaning no depth, or nan")
    cam.add_argument("--separation", type=_number, metavar="S", help="a fraction of the width [0.03]")
    cam.add_argument("--convergence", type=_number, metavar="C")
    cam.add_argument("--interaxial", type=_number, metavar="D", help="a renderer's rig, with --fov")
    cam.add_argument("--fov", type=_number, metavar="DEG", help="the rig camera's horizontal field of view")
    cam.add_argument("--relative-depth", action="store_true", help="relative inverse depth: 0 farthest .. 1 nearest")
    cam.add_argument("--max-parallax", type=_number, metavar="F", help="--relative-depth: a fraction of the width [0.03]")
    cam.add_argument("--zero-plane", type=_number, metavar="V", help="--relative-depth: the value on the screen [0.5]")
    cam.add_argument("--disparity", action="store_true", help="depth is a disparity map in pixels")
    cam.add_argument("--direction", metavar="DIR", help="centre (both eyes), left-to-right or right-to-left [centre]")
    opt = p.add_argument_group("reprojection options (as warp and pair)")
    opt.add_argument("--method", default="exact", metavar="NAME")
    opt.add_argument("--max-negative-parallax", type=_number, metavar="PX")
    opt.add_argument("--hole-threshold", type=_number, default=1.0, metavar="PX")
    opt.add_argument("--fill", default="background", metavar="MODE")
    opt.add_argument("--edge", default="clamp", metavar="MODE")
    opt.add_argument("--dilate-depth", type=int, default=0, metavar="R")
    opt.add_argument("--probe-parallax", type=_number, metavar="PX")
    opt.add_argument("--march-steps", type=int, default=16, metavar="N")
    opt.add_argument("--secant-max-steps", type=int, default=256, metavar="N")
    opt.add_argument("--arch", metavar="NAME")
    opt.add_argument("--threads", type=int, metavar="N", help="the library's threads per frame [every core]")
    run = p.add_argument_group("running")
    run.add_argument("--segment-frames", type=int, metavar="N", help="frames per segment [250]")
    run.add_argument("--resume", action="store_true", help="skip the segments an interrupted run finished")
    run.add_argument("--workers", type=int, metavar="N", help="a local Dask cluster of N processes")
    run.add_argument("--scheduler", metavar="ADDRESS", help="a running dask.distributed scheduler")
    run.add_argument("--retries", type=int, default=2, metavar="N", help="Dask reruns of a failed segment [2]")
    run.add_argument("--quiet", action="store_true", help="no progress bar")


def _scene_parser(commands):
    p = commands.add_parser("scene-video", help="a built-in scene along a camera path, as videos",
                            description="Renders a built-in scene along a short camera path (reproject.video."
                                        "scene_video) and prints the convert command that turns it into 3D.")
    p.add_argument("--out-dir", required=True, metavar="DIR")
    p.add_argument("--scene", default="room", metavar="NAME")
    p.add_argument("--width", type=int, default=640, metavar="N")
    p.add_argument("--height", type=int, default=360, metavar="N")
    p.add_argument("--frames", type=int, default=48, metavar="N")
    p.add_argument("--fps", type=int, default=24, metavar="R")
    p.add_argument("--sway", type=_number, default=2.0, metavar="D", help="sideways travel, interaxials [2]")
    p.add_argument("--quiet", action="store_true")


_EXIT_CODES = {"settings": 2, "input": 3, "output": 4, "failure": 1}
_STOPPING = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT)


class _Stopped(KeyboardInterrupt):
    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _stop(signum, frame):
    # Once the outputs are going into place the run has produced them: stopping then would report
    # "no partial output left" beside complete outputs. The signal is let pass; the run ends as
    # it would have a moment later.
    if video._outputs_committing():
        return
    raise _Stopped(signum)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m reproject", description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    _convert_parser(commands)
    _scene_parser(commands)
    args = parser.parse_args(argv)
    for signum in _STOPPING:  # a polite kill cleans up as Ctrl-C does
        signal.signal(signum, _stop)
    quiet = args.quiet or not sys.stderr.isatty()
    try:
        if args.command == "scene-video":
            flags = video.scene_video(args.out_dir, scene=args.scene, width=args.width, height=args.height,
                                      frames=args.frames, fps=args.fps, sway=args.sway, quiet=quiet)
            d = args.out_dir.rstrip("/")
            print(f"python3 -m reproject convert --color {d}/centre.mkv --depth {d}/depth.mkv "
                  f"--encoding {flags['encoding']} --depth-scale {flags['depth_scale']} "
                  f"--separation {flags['separation']:g} --convergence {flags['convergence']:g} --out {d}/sbs.mkv")
            return 0
        outputs = video.convert(
            args.color, args.depth, args.out, layout=args.layout, suffix=args.suffix, codec=args.codec,
            pixel_format=args.pixel_format, crf=args.crf, fps=args.fps, encoding=args.encoding, near=args.near,
            far=args.far, depth_scale=args.depth_scale, unknown_depth=args.unknown_depth, separation=args.separation,
            convergence=args.convergence, interaxial=args.interaxial, fov=args.fov, relative_depth=args.relative_depth,
            max_parallax=args.max_parallax, zero_plane=args.zero_plane, disparity=args.disparity,
            direction=args.direction, method=args.method, max_negative_parallax=args.max_negative_parallax,
            hole_threshold=args.hole_threshold, hole_fill=args.fill, edge=args.edge, dilate_depth=args.dilate_depth,
            probe_parallax=args.probe_parallax, march_steps=args.march_steps, secant_max_steps=args.secant_max_steps,
            arch=args.arch, threads=args.threads, segment_frames=args.segment_frames, resume=args.resume,
            workers=args.workers, scheduler=args.scheduler, retries=args.retries, quiet=quiet)
        # The outputs are in place: from here on a stop signal is ignored, to the end of the
        # process. (_stop lets it pass only while the module's flag says so; and at exit Python puts
        # back the default action, dying of the signal, for every signal it has a handler for but
        # not for an ignored one: a SIGTERM during the interpreter's shutdown ended a finished run
        # "killed", its complete output beside it, in one test run of tests/python/test_video_runs.py.)
        for signum in _STOPPING:
            signal.signal(signum, signal.SIG_IGN)
        print("wrote " + ", ".join(outputs))
        return 0
    except video.ConvertError as error:
        print(f"reproject: error: {error}", file=sys.stderr)
        return _EXIT_CODES.get(error.kind, 1)
    except (ValueError, TypeError) as error:
        print(f"reproject: error: {error}", file=sys.stderr)
        return 2
    except MemoryError:
        print("reproject: error: out of memory", file=sys.stderr)
        return 1
    except KeyboardInterrupt as stop:
        print("reproject: interrupted (no partial output left)", file=sys.stderr)
        sys.stderr.flush()
        # Die of the signal, as the C++ tool does, so that a shell running this in a loop stops too.
        signum = getattr(stop, "signum", signal.SIGINT)
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return 128 + signum


if __name__ == "__main__":
    sys.exit(main())
