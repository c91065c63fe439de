"""Files and pictures: VTU/PVD, member diagrams (matplotlib), pyvista rendering, simulation files."""
