#!/usr/bin/env python3
"""Installs MaterialX's data library (libraries/ of MaterialX 1.39.4) for gonio to read at
run time, from the npm package @needle-tools/materialx 1.4.6 (docs/materialx.md, "The data
library"). Nothing of it is committed: it is fetched with npm's ordinary client into DEST
and gonio finds it through GONIO_MTLX_LIBRARIES=DEST/libraries.

    scripts/materialx_libraries.py DEST

The package carries the library inside Emscripten's file package
(bin/JsMaterialXGenShader.data.txt, the files concatenated) whose table of contents
({filename, start, end} per file) is in bin/JsMaterialXGenShader.js; each libraries/ file
is cut out of it by that table. Prints the folder to set GONIO_MTLX_LIBRARIES to.
"""

import os
import re
import subprocess
import sys
import tarfile

PACKAGE = "@needle-tools/materialx@1.4.6"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    dest = os.path.abspath(sys.argv[1])
    os.makedirs(dest, exist_ok=True)
    tgz = os.path.join(dest, "needle-tools-materialx-1.4.6.tgz")
    if not os.path.exists(tgz):
        subprocess.run(["npm", "pack", PACKAGE, "--silent", "--pack-destination", dest], check=True,
                       stdout=subprocess.DEVNULL)
    with tarfile.open(tgz) as t:
        js = t.extractfile("package/bin/JsMaterialXGenShader.js").read().decode("utf-8")
        data = t.extractfile("package/bin/JsMaterialXGenShader.data.txt").read()
    entries = re.findall(r'\{filename:"(/libraries/[^"]+)",start:(\d+),end:(\d+)', js)
    if not entries:
        sys.exit("no libraries/ table found in the package (a different layout than 1.4.6's)")
    for name, start, end in entries:
        path = os.path.join(dest, name.lstrip("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data[int(start):int(end)])
    print(os.path.join(dest, "libraries"))


if __name__ == "__main__":
    main()
