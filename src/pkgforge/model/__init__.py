"""Everything read from a package's own files (package.xml, CMakeLists.txt, setup.py, RViz configs), plus distro data and naming rules."""
