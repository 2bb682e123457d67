#!/usr/bin/env python3
"""Runs every fenced block of README.md and docs/*.md as a reader would paste it (issue 55).

Usage: run_doc_blocks.py --source SOURCE_DIR --build BUILD_DIR [--jobs N] [--keep] [--list]
                         [--only FILE.md ...] [--languages sh python ...] [--verbose]
                         [--timeout SECONDS]

Which blocks, and how each runs:
  * Every fence in README.md and docs/*.md (docs/design/*.md too) must name its language,
    one of sh, python, cpp, cmake, json, text; a fence without one fails the test, so no
    block escapes it. docs/benchmarks-history.md is left out: it is a record of what was
    measured then, with the commands of then (some name programs and options since
    removed); docs/benchmarks.md holds the current commands and is checked.
  * ```sh      bash with `set -eo pipefail`, the build's bin/ (gonio) first on PATH,
               PYTHONPATH=BUILD/python, and `python3` the interpreter the module is built
               for (Python3_EXECUTABLE of BUILD/CMakeCache.txt).
  * ```python  that interpreter, same environment.
  * ```cpp     compiled with the build's C++ compiler (CMAKE_CXX_COMPILER) as C++20 and
               linked against gonio installed to a temporary prefix (`cmake --install
               BUILD --prefix TMP`, as tests/consumer/run.sh does), with the flags of
               `pkg-config --cflags --libs gonio` (gonio-render when the block includes a
               <gonio/render/...> header), then run.
  * ```cmake   a whole CMakeLists.txt: configured against the same prefix
               (CMAKE_PREFIX_PATH) and built; each source file it names that the block
               does not provide is an empty `int main() {}`.
  * ```json    parsed: one JSON text, or several one after another (JSON lines).
  * ```text    not run: program output, error messages, formulas, usage synopses with
               placeholders (SCENE.json, N), file layouts.
  A block that cannot run here (needs root, a network, a cluster, a browser on screen, or
  minutes of CPU) carries the marker `<!-- not run: REASON -->` on the line before its
  fence; it is counted and its reason printed. Skipped sh blocks are still checked by
  `bash -n` and skipped python blocks by compile().

Where blocks run: each document gets a scratch directory of its own, in which its blocks
run in order (a later block may read what an earlier one wrote, as a reader's shell
would). The directory holds a symbolic link to every top-level entry of the source tree
(scenes/, data/, tests/, scripts/, python/, ...) except docs/, which is copied (blocks
that regenerate a figure write into the copy, never into the repository), and `build`, a
link to BUILD_DIR (so `build/bin/gonio` and `build/python` resolve). Files a block writes
land in the scratch directory, which is removed at the end (--keep keeps it).
Documents run side by side, --jobs at a time (default 2).

Exit status 0 when every block that runs passes, 1 otherwise (each failure printed with
its file, line, output and status), 2 for bad usage.
"""

import argparse
import concurrent.futures
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

LANGUAGES = ("sh", "python", "cpp", "cmake", "json", "text")
RUNNABLE = ("sh", "python", "cpp", "cmake")
EXCLUDED = {"docs/benchmarks-history.md"}
MARKER = re.compile(r"^\s*<!--\s*not run:\s*(.*?)\s*-->\s*$")
OPEN_FENCE = re.compile(r"^(\s*)```(.*)$")
BLOCK_TIMEOUT = 120  # seconds; each block is meant to take a few


class Block:
    def __init__(self, doc, line, lang, text, skip_reason):
        self.doc, self.line, self.lang, self.text, self.skip_reason = doc, line, lang, text, skip_reason

    def where(self):
        return f"{self.doc}:{self.line}"


def documents(source):
    docs = ["README.md"]
    for root, _, files in os.walk(os.path.join(source, "docs")):
        for f in files:
            if f.endswith(".md"):
                rel = os.path.relpath(os.path.join(root, f), source)
                if rel not in EXCLUDED:
                    docs.append(rel)
    return sorted(docs, key=lambda d: (d != "README.md", d))


def extract(source, doc, errors):
    """The fenced blocks of one document, with their language and marker."""
    lines = open(os.path.join(source, doc), encoding="utf-8").read().split("\n")
    blocks, i = [], 0
    while i < len(lines):
        m = OPEN_FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, lang = m.group(1), m.group(2).strip()
        start = i + 1
        body = []
        i += 1
        while i < len(lines) and not re.match(r"^\s*```\s*$", lines[i]):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i].lstrip())
            i += 1
        if i == len(lines):
            errors.append(f"{doc}:{start}: a fence that is never closed")
        i += 1
        reason = None
        k = start - 2
        while k >= 0 and not lines[k].strip():
            k -= 1
        if k >= 0 and MARKER.match(lines[k]):
            reason = MARKER.match(lines[k]).group(1)
            if not reason:
                errors.append(f"{doc}:{start}: a `not run` marker must say why")
        if lang not in LANGUAGES:
            errors.append(f"{doc}:{start}: fence language '{lang}' is none of {', '.join(LANGUAGES)} "
                          "(```text for output and synopses)")
            continue
        if reason is not None and lang not in RUNNABLE:
            errors.append(f"{doc}:{start}: a `not run` marker on a ```{lang} block, which is never run")
        blocks.append(Block(doc, start, lang, "\n".join(body) + "\n", reason))
    return blocks


def read_cache(build):
    cache = {}
    with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^([A-Za-z0-9_]+):[A-Z]+=(.*)$", line.rstrip("\n"))
            if m:
                cache[m.group(1)] = m.group(2)
    return cache


class Runner:
    def __init__(self, args):
        self.source = os.path.abspath(args.source)
        self.build = os.path.abspath(args.build)
        cache = read_cache(self.build)
        self.cxx = cache.get("CMAKE_CXX_COMPILER") or "c++"
        self.python = cache.get("Python3_EXECUTABLE") or shutil.which("python3")
        self.cmake = shutil.which("cmake") or "cmake"
        self.tmp = tempfile.mkdtemp(prefix="gonio-docs.")
        self.keep = args.keep
        self.timeout = args.timeout
        self.prefix = None
        self.prefix_lock = threading.Lock()
        bin_dir = os.path.join(self.tmp, "bin")
        os.mkdir(bin_dir)
        os.symlink(self.python, os.path.join(bin_dir, "python3"))
        self.env = dict(os.environ)
        self.env["PATH"] = os.pathsep.join([os.path.join(self.build, "bin"), bin_dir, self.env.get("PATH", "")])
        self.env["PYTHONPATH"] = os.path.join(self.build, "python")
        self.env["PYTHONDONTWRITEBYTECODE"] = "1"
        self.env["MPLBACKEND"] = "Agg"
        for k in ("GONIO_TEST_SCALE",):
            self.env.pop(k, None)

    def scratch(self, doc):
        d = os.path.join(self.tmp, doc.replace("/", "_").replace(".md", ""))
        os.mkdir(d)
        for entry in os.listdir(self.source):
            if entry in (".git", "docs") or entry == "build" or entry.startswith("build-"):
                continue
            os.symlink(os.path.join(self.source, entry), os.path.join(d, entry))
        os.symlink(self.build, os.path.join(d, "build"))
        shutil.copytree(os.path.join(self.source, "docs"), os.path.join(d, "docs"), symlinks=True)
        return d

    def installed_prefix(self):
        """gonio installed once to a temporary prefix, as tests/consumer/run.sh does."""
        with self.prefix_lock:
            if self.prefix is None:
                prefix = os.path.join(self.tmp, "prefix")
                r = subprocess.run([self.cmake, "--install", self.build, "--prefix", prefix],
                                   capture_output=True, text=True)
                if r.returncode != 0:
                    raise RuntimeError(f"cmake --install {self.build} failed:\n{r.stdout}{r.stderr}")
                self.prefix = prefix
            return self.prefix

    def run(self, cmd, cwd, env=None, timeout=None):
        """(status, stdout + stderr) of cmd; on a timeout the whole process group (a server a
        block started, say) is killed, and the status is -1."""
        timeout = timeout or self.timeout
        p = subprocess.Popen(cmd, cwd=cwd, env=env or self.env, stdin=subprocess.DEVNULL,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             errors="replace", start_new_session=True)
        try:
            out, _ = p.communicate(timeout=timeout)
            return p.returncode, out
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            out, _ = p.communicate()
            return -1, (out or "") + f"\n(timed out after {timeout} s)"

    def block_file(self, cwd, block, n, suffix):
        path = os.path.join(cwd, f".doc_block_{n}{suffix}")
        with open(path, "w", encoding="utf-8") as f:
            f.write(block.text)
        return path

    def run_block(self, cwd, block, n):
        """(passed, output) for one block."""
        if block.lang == "json":
            try:
                dec, text, pos, values = json.JSONDecoder(), block.text, 0, 0
                while True:
                    while pos < len(text) and text[pos].isspace():
                        pos += 1
                    if pos == len(text):
                        break
                    _, pos = dec.raw_decode(text, pos)
                    values += 1
                return values > 0, "" if values else "no JSON value"
            except json.JSONDecodeError as e:
                return False, f"not JSON: {e}"
        if block.lang == "sh":
            if block.skip_reason is not None:
                status, out = self.run(["bash", "-n", self.block_file(cwd, block, n, ".sh")], cwd)
                return status == 0, out
            script = "set -eo pipefail\n" + block.text
            status, out = self.run(["bash", "-c", script, "doc-block"], cwd)
            return status == 0, out + ("" if status == 0 else f"\n(exit status {status})")
        if block.lang == "python":
            path = self.block_file(cwd, block, n, ".py")
            if block.skip_reason is not None:
                status, out = self.run([self.python, "-c", "import sys; compile(open(sys.argv[1]).read(), sys.argv[1], 'exec')", path], cwd)
                return status == 0, out
            status, out = self.run([self.python, path], cwd)
            return status == 0, out + ("" if status == 0 else f"\n(exit status {status})")
        if block.lang == "cpp":
            prefix = self.installed_prefix()
            pc_dirs = [os.path.join(root) for root, _, files in os.walk(prefix) if "gonio.pc" in files]
            env = dict(self.env)
            env["PKG_CONFIG_PATH"] = os.pathsep.join(pc_dirs)
            package = "gonio-render" if "<gonio/render/" in block.text else "gonio"
            status, flags = self.run(["pkg-config", "--cflags", "--libs", package], cwd, env)
            if status != 0:
                return False, f"pkg-config --cflags --libs {package}: {flags}"
            src = self.block_file(cwd, block, n, ".cpp")
            exe = os.path.join(cwd, f".doc_block_{n}")
            status, out = self.run([self.cxx, "-std=c++20", "-O1", src, "-o", exe] + flags.split(), cwd, env,
                                   timeout=240)
            if status != 0:
                return False, f"compiling with `pkg-config --cflags --libs {package}`:\n{out}"
            env["LD_LIBRARY_PATH"] = os.pathsep.join(sorted({os.path.dirname(d) for d in pc_dirs}))
            status, run_out = self.run([exe], cwd, env)
            return status == 0, run_out + ("" if status == 0 else f"\n(exit status {status})")
        if block.lang == "cmake":
            prefix = self.installed_prefix()
            project = os.path.join(cwd, f".doc_block_{n}_project")
            os.mkdir(project)
            with open(os.path.join(project, "CMakeLists.txt"), "w", encoding="utf-8") as f:
                f.write(block.text)
            for name in set(re.findall(r"([\w./-]+\.cpp)\b", block.text)):
                with open(os.path.join(project, name), "w", encoding="utf-8") as f:
                    f.write("int main() {}\n")
            status, out = self.run([self.cmake, "-S", project, "-B", os.path.join(project, "build"),
                                    f"-DCMAKE_PREFIX_PATH={prefix}", f"-DCMAKE_CXX_COMPILER={self.cxx}"], cwd)
            if status == 0:
                status, out2 = self.run([self.cmake, "--build", os.path.join(project, "build")], cwd, timeout=240)
                out += out2
            return status == 0, out
        return True, ""

    def run_document(self, doc, blocks):
        cwd = self.scratch(doc)
        results = []
        for n, block in enumerate(blocks):
            t0 = time.monotonic()
            try:
                passed, out = self.run_block(cwd, block, n)
            except Exception as e:  # a broken install, a missing tool: the block fails, named
                passed, out = False, f"{type(e).__name__}: {e}"
            results.append((block, passed, out, time.monotonic() - t0))
        return results

    def cleanup(self):
        if self.keep:
            print(f"scratch directories kept in {self.tmp}")
        else:
            shutil.rmtree(self.tmp, ignore_errors=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--source", required=True)
    p.add_argument("--build", required=True)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--keep", action="store_true", help="keep the scratch directories")
    p.add_argument("--list", action="store_true", help="list the blocks, run nothing")
    p.add_argument("--verbose", action="store_true", help="print every block's output")
    p.add_argument("--timeout", type=float, default=BLOCK_TIMEOUT,
                   help=f"seconds a block may take (default {BLOCK_TIMEOUT})")
    p.add_argument("--only", nargs="+", help="only these documents (paths relative to the source)")
    p.add_argument("--languages", nargs="+", choices=LANGUAGES, default=list(LANGUAGES),
                   help="only blocks of these languages (default: all)")
    args = p.parse_args()

    errors = []
    docs = documents(args.source)
    if args.only:
        unknown = [d for d in args.only if d not in docs]
        if unknown:
            print(f"run_doc_blocks: not a checked document: {', '.join(unknown)}", file=sys.stderr)
            return 2
        docs = args.only
    per_doc = {d: [b for b in extract(args.source, d, errors) if b.lang in args.languages] for d in docs}
    blocks = [b for d in docs for b in per_doc[d]]
    if args.list:
        for b in blocks:
            print(f"{b.where()} {b.lang}" + (f" (not run: {b.skip_reason})" if b.skip_reason else ""))
        for e in errors:
            print(f"error: {e}")
        return 1 if errors else 0

    runner = Runner(args)
    t0 = time.monotonic()
    results = []
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = [pool.submit(runner.run_document, d, per_doc[d]) for d in docs if per_doc[d]]
            for f in futures:
                results.extend(f.result())
    finally:
        runner.cleanup()

    failed = [(b, out) for b, passed, out, _ in results if not passed]
    for b, passed, out, seconds in results:
        state = "ok" if passed else "FAILED"
        what = "checked, not run" if b.skip_reason is not None else ("parsed" if b.lang == "json" else
                                                                    "not code" if b.lang == "text" else "ran")
        print(f"{b.where()} {b.lang} {what}: {state} ({seconds:.1f} s)")
        if args.verbose and passed and out.strip():
            print("    " + out.rstrip().replace("\n", "\n    "))
    for b, out in failed:
        print(f"\n==== {b.where()} ```{b.lang} FAILED\n{b.text}---- output:\n{out.rstrip()}\n")
    for e in errors:
        print(f"error: {e}")

    ran = [b for b, *_ in results if b.lang in RUNNABLE and b.skip_reason is None]
    skipped = [b for b, *_ in results if b.skip_reason is not None]
    by_lang = lambda bs: ", ".join(f"{l} {sum(1 for b in bs if b.lang == l)}" for l in RUNNABLE
                                   if any(b.lang == l for b in bs))
    print(f"\n{len(results)} blocks in {len(docs)} documents ({time.monotonic() - t0:.0f} s): "
          f"{len(ran)} run ({by_lang(ran)}), "
          f"{sum(1 for b in blocks if b.lang == 'json')} JSON parsed, "
          f"{sum(1 for b in blocks if b.lang == 'text')} text, {len(skipped)} not run"
          + (f" ({by_lang(skipped)}):" if skipped else ""))
    for b in skipped:
        print(f"  {b.where()} {b.lang}: {b.skip_reason}")
    if failed or errors:
        print(f"{len(failed)} blocks failed, {len(errors)} errors", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
