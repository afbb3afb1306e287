"""The Blender add-on `bcifs_blender`, packed from this installation.

    python -m bcifs.blender zip -o bcifs_blender.zip

writes a zip that Blender ≥ 3.4 installs from Edit › Preferences › Add-ons ›
Install: the add-on (`addon.py`, as the zip's `bcifs_blender/__init__.py`)
and this `bcifs` package with its compiled module (abi3: any Python ≥ 3.9
of this platform, Blender's included) beside it, so Blender needs no pip.
Blender provides numpy, the module's one dependency.
"""

import pathlib
import zipfile

PACKAGE = pathlib.Path(__file__).resolve().parents[1]


def zip_addon(output):
    """Writes the add-on zip to `output` (through a temporary file, renamed:
    never half-written) and returns the list of its entries."""
    output = pathlib.Path(output)
    entries = [("bcifs_blender/__init__.py", PACKAGE / "blender" / "addon.py")]
    for path in sorted(PACKAGE.iterdir()):
        if path.is_file() and (path.suffix in (".py", ".pyi", ".so", ".pyd") or path.name == "py.typed"):
            entries.append((f"bcifs_blender/bcifs/{path.name}", path))
    if not any(name.endswith((".so", ".pyd")) for name, _ in entries):
        raise FileNotFoundError(f"no compiled module in {PACKAGE}: install the package (pip install ./python) first")
    partial = output.with_name(output.name + ".partial")
    with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, path in entries:
            archive.write(path, name)
    partial.replace(output)
    return [name for name, _ in entries]
