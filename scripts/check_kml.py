#!/usr/bin/env python3
"""Validates KML files against the OGC KML 2.2 schema with Google's gx extension.

    pip install fastkml lxml
    python3 scripts/check_kml.py FILE.kml [FILE.kml ...]

The schemas are the ones the fastkml package ships (ogckml22.xsd, which imports kml22gx.xsd,
atom-author-link.xsd and xAL.xsd from the same folder): nothing is fetched. Every file is
validated with lxml; each schema error is printed as FILE:LINE:COLUMN: MESSAGE. Exits 1 if
any file is invalid, 2 if a file cannot be read or parsed as XML or the schemas are missing.
"""
import argparse
import pathlib
import sys

try:
    import fastkml
    from lxml import etree
except ImportError as e:  # pragma: no cover - an install problem, not a KML one
    print(f"error: {e}: pip install fastkml lxml", file=sys.stderr)
    sys.exit(2)


def schema() -> "etree.XMLSchema":
    """The OGC KML 2.2 schema (gx imported) from fastkml's package folder."""
    path = pathlib.Path(fastkml.__file__).parent / "schema" / "ogckml22.xsd"
    if not path.is_file():
        print(f"error: no {path.name} in the fastkml package ({path.parent})", file=sys.stderr)
        sys.exit(2)
    # The imports are resolved next to the file; no network access.
    parser = etree.XMLParser(no_network=True)
    return etree.XMLSchema(etree.parse(str(path), parser))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", type=pathlib.Path, help="KML files")
    args = ap.parse_args()
    xsd = schema()
    bad = 0
    for path in args.files:
        try:
            doc = etree.parse(str(path), etree.XMLParser(no_network=True))
        except (OSError, etree.XMLSyntaxError) as e:
            print(f"error: {path}: {e}", file=sys.stderr)
            return 2
        if xsd.validate(doc):
            tracks = len(doc.findall(".//{http://www.google.com/kml/ext/2.2}Track"))
            print(f"{path}: valid KML 2.2 ({tracks} gx:Track)")
            continue
        bad += 1
        for err in xsd.error_log:
            print(f"{path}:{err.line}:{err.column}: {err.message}", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
