from pkgforge.sandbox.processes import install_signal_handlers

install_signal_handlers()  # before the slower imports: a Ctrl-C at start-up exits 130 too

from pkgforge.cli import main  # noqa: E402

main()
