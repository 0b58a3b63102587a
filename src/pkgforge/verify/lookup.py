"""What verify's result cache answers before any model is loaded: the whole workspace's entry, or
each unchanged package's (verify.cache holds the entries)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import PackageReport
from pkgforge.model.files import quick_name
from pkgforge.verify.config import Config
from pkgforge.verify.discovery import package_folders
from pkgforge.verify.distros import package_distros
from pkgforge.workspace import Workspace

if TYPE_CHECKING:
    from pkgforge.verify.cache import ResultCache
    from pkgforge.verify.pipeline import VerifyOptions


def cache_folder(workspace: Workspace) -> Path:
    """build/pkgforge-cache in a workspace (beside colcon's build folders); for a lone package
    (a repository that is one package), the user's cache folder: nothing is written beside it."""
    import hashlib

    if (workspace.root / "src").is_dir() or (workspace.root / "build").is_dir():
        build = workspace.root / "build"
        if not build.exists():
            # exist_ok: another run may create it between the check and here
            build.mkdir(exist_ok=True)
            (build / "COLCON_IGNORE").touch()  # as colcon marks it, so no crawl enters it
        return build / "pkgforge-cache"
    home = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    return home / "pkgforge" / hashlib.sha1(os.fsencode(workspace.base_path)).hexdigest()[:16]


def cache_lookup(
    workspace: Workspace, config: Config, options: VerifyOptions
) -> tuple[ResultCache, dict[Path, str], dict[Path, tuple[PackageReport, set[str]]]]:
    """(cache, package folder → key, package folder → cached report) for the packages to verify."""
    import hashlib

    from pkgforge.model.files import manifest_text, vcs_repos_files, walk_file_names
    from pkgforge.verify.cache import ResultCache, workspace_key

    cache = ResultCache(cache_folder(workspace), options.cache_key())
    every = package_folders(workspace.base_path)
    folders = [workspace.package_path.resolve()] if workspace.package_path is not None else every
    texts = {folder: manifest_text(folder) for folder in every}  # each package.xml read once
    # the .repos files name packages every check may count as the workspace's (source_repositories)
    repos = "".join(
        f"{path}\0{cache.digest(str(path)) or '-'}\0" for path in vcs_repos_files(every, workspace.base_path)
    )
    signature = workspace_key(every, texts) + hashlib.sha256(os.fsencode(repos)).hexdigest()
    keys: dict[Path, str] = {}
    hits: dict[Path, tuple[PackageReport, set[str]]] = {}
    for folder in folders:
        name = quick_name(folder, texts[folder] if folder in texts else "")
        nested: list[str] = []
        # a nested package's package.xml names it (context.nested_packages): part of the key
        files = walk_file_names(folder, None, nested) + [f"{n}/package.xml" for n in nested]
        selection = config.for_package(name, folder)
        targets = package_distros(folder, workspace, config, options)
        # a package at the root of its git repository: folder-name-mismatch says nothing of it
        clone = "|clone" if (folder / ".git").exists() else ""
        keys[folder] = cache.package_key(
            folder, files, f"{selection.key()}|{','.join(targets)}{clone}", signature
        )
        report = cache.load(folder, keys[folder])
        if report is not None:
            hits[folder] = report
    cache.save_index()
    return cache, keys, hits


def store_whole(
    cache: ResultCache | None, whole: str | None, keys: dict[Path, str], reports: list[PackageReport]
) -> None:
    """The workspace entry, when every package of the run has a valid entry (answered by the cache
    next time): the next unchanged run reads that one file."""
    if whole is None or cache is None or not (set(cache.answered) == set(keys) == {r.path for r in reports}):
        return
    from pkgforge.verify.cache import store_workspace

    try:
        outside = set().union(*(externals for externals, _ in cache.answered.values()))
        store_workspace(
            cache.folder,
            whole,
            reports,
            set().union(*(codes for _, codes in cache.answered.values())),
            {path: cache.stamps.get(path) or [] for path in outside},
        )
    except OSError:
        pass  # the per-package entries answer


def workspace_lookup(
    workspace: Workspace, config: Config, options: VerifyOptions
) -> tuple[str | None, tuple[list[PackageReport], set[str]] | None]:
    """(the whole workspace's fingerprint, (reports, codes) when its entry answers), for a run on a
    whole workspace; (None, None) for one package."""
    if workspace.package_path is not None:
        return None, None
    from pkgforge.verify.cache import load_workspace, workspace_fingerprint

    root, base = workspace.root.resolve(), workspace.base_path.resolve()
    above = [folder for folder in base.parents if folder == root or root in folder.parents]
    settings = json.dumps(
        [
            config.cli.select,
            config.cli.ignore,
            config.cli.severity,
            config.workspace,
            str(config.workspace_file),
        ],
        sort_keys=True,
        default=str,
    )
    whole = workspace_fingerprint(base, above, options.cache_key(), settings)
    if whole is None:
        return None, None
    return whole, load_workspace(cache_folder(workspace), whole)
