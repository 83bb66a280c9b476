"""Reads an Exodus II file with netCDF4 (an independent reader: no Exodus library) and prints what the tests check
as one JSON object: file format, counts, coordinates, element blocks, the element number map, side sets and element
variables. Usage: /usr/bin/python3 exodus_dump.py FILE.exo"""
import json
import sys

import netCDF4


def text(chars):
    """A netCDF char array row -> str."""
    return b"".join(c for c in chars.tolist() if c not in (b"", None)).decode().rstrip("\0")


def names(ds, var):
    return [text(row) for row in ds.variables[var][:]] if var in ds.variables else []


def main(path):
    ds = netCDF4.Dataset(path)
    ds.set_auto_mask(False)
    dims = {name: len(d) for name, d in ds.dimensions.items()}
    out = {
        "file_format": ds.file_format,
        "title": getattr(ds, "title", ""),
        "num_dim": dims["num_dim"],
        "num_nodes": dims["num_nodes"],
        "num_elem": dims["num_elem"],
        "coord_names": names(ds, "coor_names"),
        "coords": [ds.variables[c][:].tolist() for c in ("coordx", "coordy", "coordz")],
        "blocks": [],
        "side_sets": [],
        "elem_num_map": ds.variables["elem_num_map"][:].tolist() if "elem_num_map" in ds.variables else None,
        "elem_var_names": names(ds, "name_elem_var"),
        "elem_vars": {},
    }
    block_ids = ds.variables["eb_prop1"][:].tolist()
    block_names = names(ds, "eb_names")
    for b, block_id in enumerate(block_ids, start=1):
        conn = ds.variables.get("connect%d" % b)
        out["blocks"].append({
            "id": block_id,
            "name": block_names[b - 1] if block_names else "",
            "elem_type": conn.getncattr("elem_type") if conn is not None else "",
            "connect": conn[:].tolist() if conn is not None else [],
        })
        var = ds.variables.get("vals_elem_var1eb%d" % b)
        if var is not None:
            out["elem_vars"][str(block_id)] = var[0].tolist()
    if "ss_prop1" in ds.variables:
        ss_names = names(ds, "ss_names")
        for s, set_id in enumerate(ds.variables["ss_prop1"][:].tolist(), start=1):
            out["side_sets"].append({
                "id": set_id,
                "name": ss_names[s - 1] if ss_names else "",
                "elements": ds.variables["elem_ss%d" % s][:].tolist() if "elem_ss%d" % s in ds.variables else [],
                "sides": ds.variables["side_ss%d" % s][:].tolist() if "side_ss%d" % s in ds.variables else [],
            })
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv[1])
