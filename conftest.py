"""Repository-wide pytest set-up: nbval's kernels talk over Unix sockets, not TCP ports.

``make test`` runs nbval with two xdist workers, each starting a kernel per notebook. Over
TCP every kernel takes five random free ports, found by binding port 0 and closing it again,
so two kernels starting at the same moment in two processes can be handed the same port; the
client then talks to the other worker's kernel, whose key does not match, and the notebook
fails with "Kernel didn't respond in 60 seconds" (seen once in a fresh clone, on
``exercises/02-optics.ipynb``). Unix domain sockets (``transport="ipc"``, as the grader's
sandboxed kernels use) are files in a folder of each kernel's own: nothing to collide on.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile


def pytest_configure(config):
    try:
        from nbval import kernel as nbval_kernel
    except ImportError:  # nbval not installed: nothing to set up
        return
    base = nbval_kernel.KernelManager

    class IpcKernelManager(base):
        """nbval's kernel manager with the kernel's sockets in a private folder."""

        def __init__(self, **kwargs):
            folder = tempfile.mkdtemp(prefix="nbval-ipc-")
            atexit.register(shutil.rmtree, folder, ignore_errors=True)
            super().__init__(transport="ipc", ip=f"{folder}/k", **kwargs)

    # nbval.kernel.start_new_kernel builds its manager from this module-level name
    nbval_kernel.KernelManager = IpcKernelManager
