#!/usr/bin/env bash
# Writes BUILD_DIR/foldfill_blender_addon.zip (BUILD_DIR: the first argument,
# else $FOLDFILL_BUILD_DIR, else build), the zip that Blender's Preferences >
# Add-ons > Install... takes: the folder foldfill_addon/ with the add-on and,
# when the Python module was built (BUILD_DIR/python/foldfill), a copy of it,
# so that the add-on needs nothing else on a machine whose Blender runs on the
# Python the module was built for (Debian 12's Blender 3.4: Python 3.11).
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/.." && pwd)
build_dir=${1:-${FOLDFILL_BUILD_DIR:-build}}
mkdir -p "$build_dir"
build_dir=$(cd "$build_dir" && pwd)
python=${PYTHON:-$(command -v /usr/bin/python3 || command -v python3)}

"$python" - "$source_dir/blender/foldfill_addon" "$build_dir/python/foldfill" \
    "$build_dir/foldfill_blender_addon.zip" <<'PY'
import glob
import os
import sys
import zipfile

addon_dir, module_dir, zip_path = sys.argv[1:4]
files = [(os.path.join(addon_dir, "__init__.py"), "foldfill_addon/__init__.py")]
extensions = glob.glob(os.path.join(module_dir, "_foldfill*.so"))
if extensions:
    files.append((os.path.join(module_dir, "__init__.py"), "foldfill_addon/foldfill/__init__.py"))
    files += [(e, "foldfill_addon/foldfill/" + os.path.basename(e)) for e in extensions]
# Written to a temporary name and renamed, so that a failure leaves no partial zip.
with zipfile.ZipFile(zip_path + ".tmp", "w", zipfile.ZIP_DEFLATED) as z:
    for path, name in files:
        z.write(path, name)
os.replace(zip_path + ".tmp", zip_path)
print("{}: the add-on{}".format(
    zip_path, " and the foldfill module" if extensions else
    " without the foldfill module (not built: the add-on will look for it on Python's path)"))
PY
