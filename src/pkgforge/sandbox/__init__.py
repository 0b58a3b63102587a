"""Running user code (launch files, xacro) in worker subprocesses with limits: the worker entry, its fork server, the write guard, and process cleanup."""
