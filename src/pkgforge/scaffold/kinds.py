"""What `pkgforge new` can write; a module light enough for the command line to import."""

BUILD_TYPES = ("ament_cmake", "ament_python")
LAUNCH_FORMATS = ("py", "xml", "yaml")
CI_SYSTEMS = ("github", "gitlab")
