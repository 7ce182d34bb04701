#!/usr/bin/env bash
# Builds the Blender extension zip: the starcages wheel (release, abi3) into
# blender/starcages_extension/wheels/, then `starcages_extension.zip` in target/ (Blender ▸
# Preferences ▸ Get Extensions ▸ Install from Disk). Needs maturin (python3 -m pip install maturin);
# with ziglang beside it (python3 -m pip install ziglang) the wheel is built through zig for
# manylinux2014 (glibc 2.17: the Linux distributions Blender 4.2-5.x runs on), else for this
# machine's glibc.
set -euo pipefail
cd "$(dirname "$0")/.."
maturin=${MATURIN:-maturin}
out=blender/starcages_extension/wheels
rm -rf "$out" && mkdir -p "$out"
portable=()
maturin_python="$(dirname "$(command -v "$maturin")")/python"
if [ -x "$maturin_python" ] && "$maturin_python" -c 'import ziglang' 2>/dev/null; then
    export PATH="$(dirname "$maturin_python"):$PATH"
    portable=(--zig --compatibility manylinux2014)
fi
(cd crates/python && "$maturin" build --release -q "${portable[@]}" -o "../../$out")
wheel=$(basename "$out"/starcages-*.whl)
# The manifest names the wheel it carries.
sed -i "s|^wheels = .*|wheels = [\"./wheels/$wheel\"]|" blender/starcages_extension/blender_manifest.toml
rm -f target/starcages_extension.zip
(cd blender/starcages_extension && python3 -c "
import zipfile, pathlib
with zipfile.ZipFile('../../target/starcages_extension.zip', 'w', zipfile.ZIP_DEFLATED) as z:
    for p in ['blender_manifest.toml', '__init__.py', *map(str, pathlib.Path('wheels').glob('*.whl'))]:
        z.write(p)
")
echo target/starcages_extension.zip
