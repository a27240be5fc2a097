"""Draws one field output of mpmice (fields_NNNNNN.h5) the way ParaView would show
it: a cell field on the mid-z slice with each solid's particles on top.

Usage: /usr/bin/python3 docs/scripts/render_fields.py FILE.h5 OUT.png [CELL_FIELD [Z_INDEX]]
CELL_FIELD defaults to `pressure` (any dataset under /cells); Z_INDEX, the slice's cell
layer, to the middle one."""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xml.etree.ElementTree as ET  # noqa: E402


def main():
    path, out = sys.argv[1], sys.argv[2]
    field = sys.argv[3] if len(sys.argv) > 3 else "pressure"
    geo = [g for g in ET.parse(path[:-3] + ".xdmf").getroot().iter("Geometry")
           if g.get("GeometryType") == "ORIGIN_DXDYDZ"]
    fig, ax = plt.subplots(figsize=(8, 4.2))
    with h5py.File(path, "r") as h5:
        time = float(h5.attrs["time"])
        if "cells" in h5 and geo:
            origin, spacing = [list(map(float, d.text.split())) for d in geo[0].findall("DataItem")]
            data = h5["cells"][field][...]  # (z, y, x)
            nz, ny, nx = data.shape[:3]
            extent = [origin[2], origin[2] + nx * spacing[2], origin[1], origin[1] + ny * spacing[1]]
            layer = int(sys.argv[4]) if len(sys.argv) > 4 else nz // 2
            im = ax.imshow(data[layer], origin="lower", extent=extent, cmap="viridis")
            fig.colorbar(im, ax=ax, label=field)
        if "particles" in h5:
            for name, group in h5["particles"].items():
                xyz = group["position"][...]
                ax.scatter(xyz[:, 0], xyz[:, 1], s=2, c="white", edgecolors="none", label="particles: " + name)
            ax.legend(loc="upper right", fontsize=8)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("%s at t = %.4g s" % (path.split("/")[-1], time))
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
