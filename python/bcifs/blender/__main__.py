"""`python -m bcifs.blender zip -o bcifs_blender.zip`: the Blender add-on as a zip."""

import argparse
import sys

from . import zip_addon


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m bcifs.blender", description="The BC-IFS Blender add-on.")
    commands = parser.add_subparsers(dest="command", required=True)
    pack = commands.add_parser("zip", help="write the add-on zip (install it from Edit › Preferences › Add-ons › Install)")
    pack.add_argument("-o", "--output", default="bcifs_blender.zip", help="the zip to write (default: bcifs_blender.zip)")
    args = parser.parse_args(argv)
    entries = zip_addon(args.output)
    print(f"{args.output}: {len(entries)} files; in Blender: Edit › Preferences › Add-ons › Install…, then enable “BC-IFS”")
    return 0


if __name__ == "__main__":
    sys.exit(main())
