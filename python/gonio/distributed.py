"""gonio.distributed: renders, fits and checks on a Dask cluster (docs/distributed.md).

    import gonio.distributed as gd
    image = gd.render("scene.json", spp=1024, passes=64)            # a LocalCluster
    image = gd.render("scene.json", spp=1024, passes=64, scheduler="tcp://host:8786")

A render is split into passes: pass p takes the per-pixel sample indices
[p*spp//passes, (p+1)*spp//passes) of the sequences ``gonio render --spp N --seed S``
uses (``gonio render --sample-range A B``; ``gonio.render(sample_range=(A, B))``), and
returns their per-pixel sums. The sums are added in double precision by a fixed
pairwise tree over the pass indices (level by level: (0+1), (2+3), ...; an odd last one
carried up), so the image depends on (scene, spp, passes, seed) alone: the same bits
whatever the number of workers, the order in which passes finish, or a worker lost and
its tasks rerun. The tree's subtrees of BLOCK consecutive passes are reduced on the
workers; only their sums reach the client, which keeps them in a checkpoint and adds
them by the same tree.

Command line: ``python3 -m gonio.distributed render SCENE.json --spp N --passes P
-o OUT.exr [--seed S] [--scheduler ADDR | --workers W]`` (and ``fit``, ``check``).
"""

import argparse
import contextlib
import itertools
import logging
import math
import os
import stat
import sys
import time
import warnings

import numpy as np

import gonio

# Passes per subtree reduced on the workers and checkpointed as one sum. A power of two,
# so that the subtrees are the pairwise tree's own and the result does not depend on it.
BLOCK = 8


class DistributedError(Exception):
    """A bad input or an unreachable cluster: the message is the one line to print."""


# --- the fixed merge order -------------------------------------------------------------------

def pass_range(p, spp, passes):
    """The sample indices [a, b) of pass p of `passes` over spp samples per pixel."""
    return p * spp // passes, (p + 1) * spp // passes


def pairwise(items, add):
    """Reduces items level by level, (0+1), (2+3), ... with an odd last one carried up:
    the fixed summation tree of the passes. `add` may build futures or add arrays."""
    items = list(items)
    if not items:
        raise ValueError("nothing to merge")
    while len(items) > 1:
        nxt = [add(items[i], items[i + 1]) for i in range(0, len(items) - 1, 2)]
        if len(items) % 2:
            nxt.append(items[-1])
        items = nxt
    return items[0]


def normalise(total, spp):
    """The image from the per-pixel total of spp samples, as the renderer divides: times the
    float reciprocal of spp (Color /= s multiplies by 1 / s). The product of two floats is
    exact in double, so for a float total (one pass) this is the renderer's float product."""
    return (total * np.float64(np.float32(1) / np.float32(spp))).astype(np.float32)


def _add(a, b):
    # Float32 pass sums are exact in double; every addition is one IEEE double addition.
    return np.add(a, b, dtype=np.float64)


# --- work on the workers -----------------------------------------------------------------------

_SCENES = {}  # per worker process: scene key -> gonio.Scene, loaded once


def _scene_key(scene):
    """What identifies a scene to the workers' caches: a file by its absolute path, size and
    modification time (a changed file is loaded again); JSON text or a dict by its text."""
    if scene is None:
        return ("default",)
    if isinstance(scene, gonio.Scene):
        raise DistributedError("scene: give a path, JSON text or a dict (a gonio.Scene cannot be sent to workers)")
    if isinstance(scene, dict):
        import json
        return ("json", json.dumps(scene, sort_keys=True))
    s = os.fspath(scene)
    if s.lstrip().startswith("{"):
        return ("json", s)
    path = os.path.abspath(s)
    try:
        st = os.stat(path)
    except OSError as e:
        raise DistributedError("%s: %s" % (s, e.strerror or e)) from None
    return ("file", path, st.st_size, st.st_mtime_ns)


def _load(key):
    scene = _SCENES.get(key)
    if scene is None:
        src = None if key[0] == "default" else key[1]
        scene = gonio.Scene(src)
        _SCENES.clear()  # one scene per worker at a time: scenes can be large
        _SCENES[key] = scene
    return scene


def _render_pass(key, seed, a, b, threads=1):
    """The float32 per-pixel sums of the sample indices [a, b) (exact: the renderer adds in
    float). One thread by default: a worker process is one core."""
    sums = gonio.render(_load(key), seed=seed, threads=threads, sample_range=(a, b))
    return sums.astype(np.float32)


# --- the cluster ----------------------------------------------------------------------------------

def _quiet_dask():
    """Dask's own log lines off (an error is then one line), no dashboard."""
    import dask
    for name in ("distributed", "distributed.worker", "distributed.nanny", "distributed.scheduler",
                 "distributed.core", "distributed.comm", "distributed.client", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
    dask.config.set({"logging.distributed": "critical"})
    # "Port 8787 is already in use": the scheduler's HTTP server moves to another port.
    warnings.filterwarnings("ignore", module=r"distributed(\..*)?$")


def _keep_malloc_default():
    """Dask's nanny starts each worker with MALLOC_TRIM_THRESHOLD_=65536 (its
    distributed.nanny.pre-spawn-environ), which makes glibc return freed memory to the system
    at once; a renderer that frees and reallocates its buffers then pays for the pages again
    and again: 40 ms of a 640x360 pass's 113 ms here (docs/distributed.md). The workers this
    module starts keep glibc's own (adaptive) threshold. Set for this process's Dask config,
    so that a worker the nanny restarts (after a fault) gets it too."""
    import dask
    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", default={}) or {})
    if "MALLOC_TRIM_THRESHOLD_" in env:
        del env["MALLOC_TRIM_THRESHOLD_"]
        dask.config.set({"distributed.nanny.pre-spawn-environ": env})


@contextlib.contextmanager
def cluster(client=None, scheduler=None, workers=None, connect_timeout=10):
    """A dask.distributed Client: `client` itself; or one connected to `scheduler`
    ("tcp://host:8786"); or a LocalCluster of `workers` single-threaded worker processes
    (default: one per core). Closes what it opened."""
    if client is not None:
        yield client
        return
    _quiet_dask()
    from distributed import Client, LocalCluster
    if scheduler is not None:
        try:
            c = Client(scheduler, timeout=connect_timeout)
        except Exception as e:  # OSError (timeout, refused), ValueError (a bad address)
            msg = str(e).splitlines()[0] if str(e) else type(e).__name__
            raise DistributedError("cannot reach the Dask scheduler at %s: %s" % (scheduler, msg)) from None
        try:
            yield c
        finally:
            c.close()
        return
    n = workers if workers is not None else (os.cpu_count() or 1)
    if not (isinstance(n, int) and 1 <= n <= 1024):
        raise DistributedError("workers must be an integer from 1 to 1024, got %r" % (n,))
    _keep_malloc_default()
    lc = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.CRITICAL)
    c = Client(lc)
    try:
        yield c
    finally:
        c.close()
        lc.close()


# --- render ---------------------------------------------------------------------------------------

def check_render_inputs(scene, spp, passes, seed):
    """Loads the scene on the client (a missing or corrupt file is named now, before any
    cluster) and checks the numbers; returns (key, spp, seed, gonio.Scene)."""
    key = _scene_key(scene)
    try:
        loaded = _load(key)
    except ValueError as e:
        raise DistributedError(str(e)) from None
    spp = loaded.spp if spp is None else spp
    if not (isinstance(spp, (int, np.integer)) and 1 <= spp <= 1048576):
        raise DistributedError("spp must be an integer from 1 to 1048576, got %r" % (spp,))
    if not (isinstance(passes, (int, np.integer)) and 1 <= passes <= spp):
        raise DistributedError("passes must be an integer from 1 to spp (%d), got %r" % (spp, passes))
    seed = loaded.seed if seed is None else seed
    if not (isinstance(seed, (int, np.integer)) and 0 <= seed <= 2147483647):
        raise DistributedError("seed must be an integer from 0 to 2147483647, got %r" % (seed,))
    return key, int(spp), int(seed), loaded


def _load_checkpoint(path, meta, nblocks):
    """The finished blocks' sums kept in `path` for the job `meta`, each checked: a block index
    of the job, a (height, width, 3) float array of finite sums. A checkpoint whose metadata
    matches is still a file on disk: a truncated copy, another program's array or a bug must
    not become the image (a 3x3 block would otherwise broadcast into a 16x16 render)."""
    if path is None or not os.path.exists(path):
        return {}
    try:
        with np.load(path, allow_pickle=False) as z:
            saved = {k: z["meta_" + k].item() for k in meta}
            blocks = {int(i): z["block_%d" % int(i)] for i in z["done"]}
    except Exception as e:
        raise DistributedError("%s: not a readable checkpoint (%s); remove it to start anew" % (path, e)) from None
    if saved != meta:
        raise DistributedError("%s: a checkpoint of another job (%s); remove it to start anew"
                               % (path, ", ".join("%s %s" % (k, saved[k]) for k in meta if saved[k] != meta[k])))
    shape = (meta["height"], meta["width"], 3)
    for i, s in sorted(blocks.items()):
        problem = None
        if not 0 <= i < nblocks:
            problem = "block %d is not one of the job's %d blocks" % (i, nblocks)
        elif s.dtype not in (np.float32, np.float64):
            problem = "block %d holds %s values, not float sums" % (i, s.dtype)
        elif s.shape != shape:
            problem = "block %d is %s, not the image's %dx%dx3" % (i, "x".join(map(str, s.shape)) or "a scalar",
                                                                 shape[0], shape[1])
        elif not np.isfinite(s).all():
            problem = "block %d holds a NaN or infinite sum" % i
        if problem:
            raise DistributedError("%s: a damaged checkpoint (%s); remove it to start anew" % (path, problem))
    return blocks


def _save_checkpoint(path, meta, blocks):
    arrays = {"meta_" + k: np.array(v) for k, v in meta.items()}
    arrays["done"] = np.array(sorted(blocks), dtype=np.int64)
    for i, s in blocks.items():
        arrays["block_%d" % i] = s
    # Written whole under a temporary name, then renamed over the checkpoint: an interrupted
    # write (Ctrl-C, a full disk) leaves the previous checkpoint, and no temporary behind.
    tmp = path + ".tmp.npz"
    try:
        np.savez(tmp, **arrays)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def render(scene=None, spp=None, passes=16, client=None, scheduler=None, seed=None, on_pass=None,
           workers=None, checkpoint=None, every=BLOCK, progress=None, threads=1, keep_checkpoint=False):
    """The image (float32 (H, W, 3), linear) of `scene` at `spp` samples per pixel, rendered as
    `passes` tasks on a Dask cluster (see the module's docstring for the merge order).

    scene: a path (every worker must see it, and the files it names, at the same path), JSON
    text, a dict, or None (the default scene); spp, seed: None for the scene's. client /
    scheduler / workers: see cluster(). on_pass(done, preview): called on the client after
    each block of `every` passes (a power of two) with the number of passes done and the
    image of those passes so far. checkpoint: a .npz path where finished blocks' sums are
    kept; a job started again with it resumes, and it is removed when the image is done
    (keep_checkpoint=True: left for the caller to remove once the image is safely written).
    progress(done): called on the client after every pass with the number of passes done.
    threads: render threads per pass (1 for single-threaded workers; a node's cores for one
    worker per node); the image does not depend on it.
    """
    key, spp, seed, loaded = check_render_inputs(scene, spp, passes, seed)
    if not (isinstance(every, int) and every >= 1 and every & (every - 1) == 0):
        raise DistributedError("every must be a power of two, got %r" % (every,))
    meta = {"scene": repr(key), "spp": spp, "passes": passes, "seed": seed, "block": every,
            "width": loaded.width, "height": loaded.height}
    nblocks = (passes + every - 1) // every
    blocks = _load_checkpoint(checkpoint, meta, nblocks)
    todo = [i for i in range(nblocks) if i not in blocks]

    def samples_of(block_ids):
        return sum(pass_range(min((i + 1) * every, passes) - 1, spp, passes)[1] - pass_range(i * every, spp, passes)[0]
                   for i in block_ids)

    def passes_of(block_ids):
        return sum(min((i + 1) * every, passes) - i * every for i in block_ids)

    if todo:
        from distributed import as_completed
        with cluster(client, scheduler, workers) as c:
            roots, leaves = {}, set()
            for i in todo:
                block = [c.submit(_render_pass, key, seed, *pass_range(p, spp, passes), threads, pure=False)
                         for p in range(i * every, min((i + 1) * every, passes))]
                leaves.update(block)
                # The block's subtree, added on the workers; only its root comes back.
                roots[pairwise(block, lambda a, b: c.submit(_add, a, b, pure=False))] = i
            done_passes = passes_of(blocks)
            for fut in as_completed(list(roots) + [f for f in leaves if f not in roots]):
                if fut.status == "error":
                    fut.result()  # raises the worker's exception (a scene that fails to load, say)
                if fut in leaves:
                    leaves.discard(fut)
                    done_passes += 1
                    if progress is not None:
                        progress(done_passes)
                if fut not in roots:
                    continue
                i = roots.pop(fut)
                blocks[i] = fut.result()
                if checkpoint is not None:
                    _save_checkpoint(checkpoint, meta, blocks)
                if on_pass is not None:
                    done = sorted(blocks)
                    preview = normalise(pairwise([blocks[j] for j in done], _add), samples_of(done))
                    on_pass(passes_of(done), preview)
    total = pairwise([blocks[i] for i in range(nblocks)], _add)
    image = normalise(total, spp)
    if checkpoint is not None and not keep_checkpoint and os.path.exists(checkpoint):
        os.remove(checkpoint)
    return image


# --- the other operations, mapped ----------------------------------------------------------------

def _map(fn, items, client=None, scheduler=None, workers=None):
    with cluster(client, scheduler, workers) as c:
        futures = [c.submit(fn, *it, pure=False) for it in items]
        return c.gather(futures)


def _check_tables(tables):
    for t in tables:
        if not os.path.isfile(t):
            raise DistributedError("%s: no such file" % os.fspath(t))


def _check_models(models, kwargs):
    for m in models:
        gonio._gonio._check_fit_options(m, **kwargs)  # gonio.fit's own checks, in its words


def _check_surfaces(surfaces, kwargs):
    for s in surfaces:
        gonio._gonio._check_surface(s)  # gonio.measure's parse (and image load), no ray
    samples = kwargs.get("samples", 1)
    if not (isinstance(samples, int) and samples >= 1):
        raise DistributedError("measure: samples must be an integer of at least 1, got %r" % (samples,))


def _fit_one(table, model, kwargs):
    return gonio.fit(table, model, **kwargs)


def fit(tables, models, client=None, scheduler=None, workers=None, **kwargs):
    """gonio.fit over every (table, model) pair, tables major: a list of the dicts one call
    each returns (`seconds` aside, the same). kwargs: gonio.fit's (distribution, metric,
    init, stride). Every worker must see the tables at the same paths."""
    if not hasattr(gonio, "fit"):
        raise DistributedError("this gonio module was built without the fitter")
    _check_tables(tables)
    _check_models(models, kwargs)
    pairs = [(os.path.abspath(os.fspath(t)), m, kwargs) for t, m in itertools.product(tables, models)]
    return _map(_fit_one, pairs, client, scheduler, workers)


def _check_one(material, kwargs):
    return gonio.Material(material).check(**kwargs)


def check(materials, client=None, scheduler=None, workers=None, **kwargs):
    """Material(m).check(**kwargs) (`gonio check`) for every material, in order."""
    for m in materials:
        gonio.Material(m)  # a bad material fails here, on the client
    return _map(_check_one, [(m, kwargs) for m in materials], client, scheduler, workers)


def _measure_one(surface, kwargs):
    return gonio.measure(surface, **kwargs)


def measure(surfaces, client=None, scheduler=None, workers=None, outputs=None, **kwargs):
    """gonio.measure(surface, **kwargs) for every surface, in order; kwargs as gonio.measure's
    (gantry, samples, seed, ...; threads defaults to 1, one core per worker). outputs: one MERL
    table path per surface (gonio.measure's output=), on a file system the workers share."""
    kwargs.setdefault("threads", 1)
    surfaces = list(surfaces)
    _check_surfaces(surfaces, kwargs)
    if outputs is None:
        return _map(_measure_one, [(s, kwargs) for s in surfaces], client, scheduler, workers)
    outputs = [os.path.abspath(os.fspath(o)) for o in outputs]
    if len(outputs) != len(surfaces):
        raise DistributedError("measure: %d surfaces but %d outputs" % (len(surfaces), len(outputs)))
    return _map(_measure_one, [(s, dict(kwargs, output=o)) for s, o in zip(surfaces, outputs)], client, scheduler,
                workers)


def _tabulate_one(material, path):
    return gonio.Material(material).tabulate(path)


def tabulate(materials, outputs, client=None, scheduler=None, workers=None):
    """Material(m).tabulate(out) (`gonio tabulate`) for every (material, output path) pair,
    in order: the dicts one call each returns. Every worker writes its table at its path,
    so the paths must be on a file system the workers share with the client."""
    materials, outputs = list(materials), [os.path.abspath(os.fspath(o)) for o in outputs]
    if len(materials) != len(outputs):
        raise DistributedError("tabulate: %d materials but %d outputs" % (len(materials), len(outputs)))
    if len(set(outputs)) != len(outputs):
        raise DistributedError("tabulate: two materials would be written to the same file")
    for m, o in zip(materials, outputs):
        gonio.Material(m)  # a bad material fails here, on the client
        d = os.path.dirname(o)
        if not os.path.isdir(d) or not os.access(d, os.W_OK):
            raise DistributedError("%s: cannot write in %s" % (o, d))
    return _map(_tabulate_one, list(zip(materials, outputs)), client, scheduler, workers)


# --- the command line -----------------------------------------------------------------------------

class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not the usage block
        sys.stderr.write("gonio.distributed: %s (see --help)\n" % message)
        sys.exit(2)


class _Progress:
    """A bar on stderr when it is a terminal; otherwise nothing (SPEC §3: progress only on a
    terminal, so that a log holds the closing line alone)."""

    def __init__(self, total, tty=None):
        self.total = total
        self.tty = sys.stderr.isatty() if tty is None else tty

    def __call__(self, done):
        if not self.tty:
            return
        n = done * 40 // self.total
        sys.stderr.write("\rrendering [%-40s] %d/%d passes" % ("#" * n, done, self.total))
        if done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def _text_or_file(arg):
    """A JSON text, or @path to one (as the CLI's --bsdf and --surface)."""
    if arg.startswith("@"):
        with open(arg[1:]) as f:
            return f.read()
    return arg


def _check_output(path):
    """What `gonio render` checks of its -o before rendering (src/io/output_file.cpp): the
    extension, a writable directory, and a target (through a symbolic link) that is absent or
    a writable regular file, never a directory, FIFO or device. A job of hours must not end
    in a write that was bound to fail."""
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".exr", ".png"):
        raise DistributedError("-o %s: the output must end in .exr (linear) or .png (sRGB)" % path)
    target = os.path.realpath(path)
    try:
        st = os.stat(target)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise DistributedError("-o %s: cannot write the image: %s" % (path, e.strerror or e)) from None
    if st is not None:
        if stat.S_ISDIR(st.st_mode):
            raise DistributedError("-o %s: cannot write the image: it is a directory" % path)
        if not stat.S_ISREG(st.st_mode):
            raise DistributedError("-o %s: cannot write the image: it exists and is not a regular file" % path)
        if not os.access(target, os.W_OK):
            raise DistributedError("-o %s: cannot write the image: the file is read-only" % path)
    d = os.path.dirname(target)
    if not os.path.isdir(d) or not os.access(d, os.W_OK):
        raise DistributedError("-o %s: cannot write in %s" % (path, d))


def _timeout(text):
    """--timeout: seconds, a finite positive number (Dask's own error for nan or -5 is not one
    line about the option)."""
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError("must be a positive number of seconds, got %r" % text)
    return v


def main(argv=None):
    p = _Parser(prog="python3 -m gonio.distributed", description="gonio on a Dask cluster (docs/distributed.md)")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    r = sub.add_parser("render", help="render a scene as passes on a Dask cluster")
    r.add_argument("scene", nargs="?", help="scene file (JSON; default: the built-in default scene); every "
                   "worker must see it, and the files it names, at the same path")
    r.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    r.add_argument("--passes", type=int, default=16, help="tasks; pass p renders samples [p*N/P, (p+1)*N/P)")
    r.add_argument("-o", "--output", required=True, help="OUT.exr (linear) or OUT.png")
    r.add_argument("--seed", type=int, help="random seed (default: the scene's)")
    r.add_argument("--every", type=int, default=BLOCK,
                   help="passes per block added on the workers and checkpointed, a power of two (default %d; "
                        "large images: 256 or more, docs/distributed.md)" % BLOCK)
    r.add_argument("--threads", type=int, default=1, help="render threads per pass (default 1: one per worker)")
    f = sub.add_parser("fit", help="fit models to MERL tables, every pair a task; JSON lines on stdout")
    f.add_argument("tables", nargs="+", help="MERL .binary files")
    f.add_argument("--model", action="append", required=True, help="model to fit (repeat for several)")
    f.add_argument("--metric", default="log")
    c = sub.add_parser("check", help="`gonio check` of many materials; JSON lines on stdout")
    c.add_argument("materials", nargs="+", help="material JSON texts")
    c.add_argument("--seed", type=int, default=1)
    m = sub.add_parser("measure", help="`gonio measure` of many surfaces, every surface a task; one MERL table "
                       "each, written as OUTDIR/<index>.binary; JSON lines on stdout")
    m.add_argument("surfaces", nargs="+", help="surface JSON texts, or @path (as --surface)")
    m.add_argument("-o", "--output-dir", required=True, help="directory of the tables (must exist)")
    m.add_argument("--samples", type=int, default=10_000_000, help="rays per surface (as gonio measure)")
    m.add_argument("--seed", type=int, default=0)
    t = sub.add_parser("tabulate", help="`gonio tabulate` of many materials; OUTDIR/<index>.binary each")
    t.add_argument("materials", nargs="+", help="material JSON texts, or @path (as --bsdf)")
    t.add_argument("-o", "--output-dir", required=True, help="directory of the tables (must exist)")
    for q in (r, f, c, m, t):
        g = q.add_mutually_exclusive_group()
        g.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://host:8786")
        g.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
        q.add_argument("--timeout", type=_timeout, default=10.0,
                       help="seconds to wait for the scheduler of --scheduler (default 10)")
    a = p.parse_args(argv)
    import json
    try:
        if a.command == "render":
            # Every input checked here, before any cluster starts.
            _check_output(a.output)
            checkpoint = a.output + ".checkpoint.npz"
            check_render_inputs(a.scene, a.spp, a.passes, a.seed)
            if not (a.every >= 1 and a.every & (a.every - 1) == 0):
                raise DistributedError("--every must be a power of two, got %d" % a.every)
            if not 0 <= a.threads <= 1024:
                raise DistributedError("--threads must be from 0 to 1024, got %d" % a.threads)
            if a.workers is not None and not 1 <= a.workers <= 1024:
                raise DistributedError("--workers must be from 1 to 1024, got %d" % a.workers)
            t0 = time.time()
            with cluster(scheduler=a.scheduler, workers=a.workers, connect_timeout=a.timeout) as c:
                image = render(a.scene, a.spp, a.passes, client=c, seed=a.seed, checkpoint=checkpoint,
                               progress=_Progress(a.passes), every=a.every, threads=a.threads,
                               keep_checkpoint=True)
            try:
                gonio.write_image(a.output, image)
            except (ValueError, OSError) as e:
                raise DistributedError("%s (the finished passes are kept in %s)"
                                       % (str(e).splitlines()[0] if str(e) else type(e).__name__, checkpoint)) from None
            # Only now is the work safe elsewhere.
            with contextlib.suppress(FileNotFoundError):
                os.remove(checkpoint)
            sys.stderr.write("rendered %dx%d in %d passes in %.2f s\n" % (image.shape[1], image.shape[0], a.passes,
                                                                         time.time() - t0))
            print(a.output)
        elif a.command == "fit":
            _check_tables(a.tables)
            _check_models(a.model, {"metric": a.metric})
            with cluster(scheduler=a.scheduler, workers=a.workers, connect_timeout=a.timeout) as c:
                for r_ in fit(a.tables, a.model, client=c, metric=a.metric):
                    print(json.dumps(r_, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))
        elif a.command == "check":
            for m in a.materials:
                gonio.Material(m)
            with cluster(scheduler=a.scheduler, workers=a.workers, connect_timeout=a.timeout) as c:
                for r_ in check(a.materials, client=c, seed=a.seed):
                    print(json.dumps(r_, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))
        elif a.command in ("measure", "tabulate"):
            inputs = [_text_or_file(x) for x in (a.surfaces if a.command == "measure" else a.materials)]
            if not os.path.isdir(a.output_dir):
                raise DistributedError("-o %s: no such directory" % a.output_dir)
            outs = [os.path.join(a.output_dir, "%d.binary" % i) for i in range(len(inputs))]
            # Every input checked here, before any cluster starts.
            if a.command == "tabulate":
                for x in inputs:
                    gonio.Material(x)
            elif a.samples < 1:
                raise DistributedError("--samples must be at least 1, got %d" % a.samples)
            else:
                _check_surfaces(inputs, {})
            with cluster(scheduler=a.scheduler, workers=a.workers, connect_timeout=a.timeout) as c:
                if a.command == "measure":
                    results = measure(inputs, client=c, samples=a.samples, seed=a.seed, outputs=outs)
                else:
                    results = tabulate(inputs, outs, client=c)
            for o, r_ in zip(outs, results):
                line = {"file": o}
                line.update({k: v for k, v in r_.items() if isinstance(v, (int, float, str, bool))})
                print(json.dumps(line, default=lambda v: v.tolist() if hasattr(v, "tolist") else str(v)))
    except (DistributedError, ValueError, OSError) as e:
        sys.stderr.write("gonio.distributed: %s\n" % (str(e).splitlines()[0] if str(e) else type(e).__name__))
        return 1
    except KeyboardInterrupt:
        sys.stderr.write("gonio.distributed: interrupted (finished passes are in the checkpoint)\n")
        return 130
    return 0


if __name__ == "__main__":
    # Through the package's module, not __main__: Dask pickles __main__'s functions by value
    # (with the scene cache), the package's by name.
    from gonio.distributed import main as _main
    sys.exit(_main())
