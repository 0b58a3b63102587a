"""`pkgforge new`: writing a package (templates, kinds, placeholder meshes, `--from-urdf`)."""
