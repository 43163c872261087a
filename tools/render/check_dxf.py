#!/usr/bin/env python3
"""Opens actag-render DXF files with an independent reader (ezdxf, Debian's
python3-ezdxf) and checks what a cutting service needs: R12 (AC1009),
millimetres, no audit errors, closed outline and cut-out polylines, holes.
usage: check_dxf.py FILE.dxf...   (exit status 1 on any problem)"""
import sys

import ezdxf
from ezdxf import recover

bad = 0
for path in sys.argv[1:]:
    doc, auditor = recover.readfile(path)
    msp = doc.modelspace()
    layers = {}
    for e in msp:
        layers.setdefault(e.dxf.layer, []).append(e)
    problems = []
    if doc.dxfversion != "AC1009":
        problems.append("version %s, not AC1009 (R12)" % doc.dxfversion)
    if doc.header.get("$INSUNITS", 0) != 4:
        problems.append("units are not millimetres")
    if auditor.has_errors or auditor.has_fixes:
        problems.append("audit: %d errors, %d fixes" % (len(auditor.errors), len(auditor.fixes)))
    outline = [e for e in layers.get("OUTLINE", []) if e.dxftype() == "POLYLINE"]
    cutouts = [e for e in layers.get("CUTOUT", []) if e.dxftype() == "POLYLINE"]
    holes = [e for e in layers.get("HOLES", []) if e.dxftype() == "CIRCLE"]
    if not outline or not all(p.is_closed for p in outline + cutouts):
        problems.append("outline/cut-outs missing or not closed")
    if not holes:
        problems.append("no screw holes")
    print("%s: ezdxf %s, %s, %d outline, %d cut-out polylines, %d holes%s" % (
        path, ezdxf.__version__, doc.dxfversion, len(outline), len(cutouts), len(holes),
        (": " + "; ".join(problems)) if problems else ": OK"))
    bad += bool(problems)
sys.exit(1 if bad else 0)
