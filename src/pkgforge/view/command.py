"""What `pkgforge view TARGET` renders: a package or workspace (verify's models), one model file
in a workspace package, a model installed in a ROS prefix (share/<package>/...), or a package name."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.errors import PkgforgeError
from pkgforge.urdf import XACRO_MODEL_SUFFIXES
from pkgforge.view import Artifacts

if TYPE_CHECKING:
    from pkgforge.tree import InstallTree
    from pkgforge.urdf.select import ModelResult
    from pkgforge.verify.pipeline import VerifyOptions


def _installed_prefix(file: Path) -> tuple[Path, str] | None:
    """(prefix, package) when FILE is inside <prefix>/share/<package>/ with a package.xml."""
    for folder in file.parents:
        if folder.parent.name == "share" and (folder / "package.xml").is_file():
            return folder.parent.parent, folder.name
    return None


def _package_folder(file: Path) -> Path | None:
    return next((f for f in file.parents if (f / "package.xml").is_file()), None)


def _by_name(name: str) -> Path:
    from pkgforge.model.files import quick_name
    from pkgforge.verify.discovery import package_folders
    from pkgforge.workspace import locate

    workspace = locate(Path.cwd())
    for folder in package_folders(workspace.base_path):
        if quick_name(folder) == name:
            return folder
    raise PkgforgeError(
        f"'{name}' is neither a file or folder nor a package of the workspace at "
        f"{workspace.root}: give a package, a workspace, or a .urdf/.xacro file"
    )


def run_view(target: str, artifacts: Artifacts, options: VerifyOptions) -> None:
    """Render through verify's own model processing; `options` are VerifyOptions."""
    path = Path(target)
    if not path.exists():
        path = _by_name(target)
    path = path.resolve()
    if path.is_file():
        if not path.name.endswith(XACRO_MODEL_SUFFIXES):
            raise PkgforgeError(f"{path} is not a robot model (.urdf or .xacro)")
        _one_model(path, artifacts, options)
    else:
        from pkgforge.verify.config import Selection
        from pkgforge.verify.pipeline import verify

        # the tree and the models only: urdf-invalid is the one check that needs them
        options.selection, options.use_cache, options.on_models = Selection(["PF401"], []), False, artifacts
        verify(path, options)


def _one_model(file: Path, artifacts: Artifacts, options: VerifyOptions) -> None:
    from pkgforge.launch.resolve import source_of
    from pkgforge.urdf import select as robot_models

    installed = _installed_prefix(file)
    folder = _package_folder(file)
    if installed is not None or folder is None:
        import tempfile
        import time

        from pkgforge.tree import InstallTree, _index

        prefixes = [installed[0]] if installed else []
        # xacro is user code: its worker may write only in an empty temporary folder (sandbox/guard.py)
        sandbox = tempfile.TemporaryDirectory(prefix="pkgforge-view-")
        tree = InstallTree(
            "existing", prefixes, _temporary=sandbox, root=Path(sandbox.name), sealed=time.time_ns()
        )
        tree.packages = _index(prefixes)
        try:
            package = installed[1] if installed else file.parent.name
            result = robot_models.ModelResult(package, file, file, dict(options.launch_arguments))
            _render(artifacts, tree, result, options)
        finally:
            tree.close()
        return
    from pkgforge.verify.explain import _installed

    with _installed(folder, file, options) as (tree, installed_file, package, owner):
        result = robot_models.ModelResult(
            package, installed_file, source_of(installed_file, tree, owner), dict(options.launch_arguments)
        )
        _render(artifacts, tree, result, options)


def _render(artifacts: Artifacts, tree: InstallTree, result: ModelResult, options: VerifyOptions) -> None:
    """Process the model (xacro in a worker: it is user code) and draw it."""
    from pkgforge.launch.resolve import WorkerLimits
    from pkgforge.urdf import select as robot_models

    (result,) = robot_models.process(
        [result],
        tree,
        jobs=1,
        timeout=options.launch_timeout,
        limits=WorkerLimits(options.launch_timeout, options.worker_memory),
    )
    if result.status not in ("ok",):
        error = result.error or {}
        where = f"{error.get('file') or result.installed}:{error.get('line') or ''}".rstrip(":")
        raise PkgforgeError(f"{where}: cannot render: {result.status}: {error.get('message') or 'no links'}")
    artifacts(tree, [result])
