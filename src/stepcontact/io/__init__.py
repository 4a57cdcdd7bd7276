"""Input and output beside results: model files (TOML), Gmsh meshes, ParaView export."""
