#!/usr/bin/env bash
# Builds the Blender extension zip: the starcages wheel (release, abi3) into
# blender/starcages_extension/wheels/, then `starcages_extension.zip` in target/ (Blender ▸
# Preferences ▸ Get Extensions ▸ Install from Disk). Needs maturin (python3 -m pip install maturin).
set -euo pipefail
cd "$(dirname "$0")/.."
maturin=${MATURIN:-maturin}
out=blender/starcages_extension/wheels
rm -rf "$out" && mkdir -p "$out"
(cd crates/python && "$maturin" build --release -q -o "../../$out")
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
