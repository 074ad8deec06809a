"""The kernel manager of the notebook runs: kernels that start and stop without noise.

jupyter_client's defaults make every notebook run print two things that are not problems:

- ipykernel warns "Kernel is running over TCP without encryption" at each start: the runner's kernels are
  local child processes, so they talk over IPC (Unix domain sockets in the user's Jupyter runtime folder,
  private to the user) where the platform has it, and TCP on localhost elsewhere;
- a graceful shutdown first interrupts the kernel (SIGINT) and then asks it to quit; a kernel caught
  inside a message handler by that SIGINT logs "ERROR | KeyboardInterrupt caught in kernel" although
  nothing failed. A kernel that has finished every cell is idle, so the shutdown skips the interrupt
  and only sends the shutdown request (escalating to SIGTERM/SIGKILL as before if it does not exit).
"""

from __future__ import annotations

import os
import tempfile

from jupyter_client.manager import AsyncKernelManager
from traitlets import default

__all__ = ["QuietKernelManager"]


class QuietKernelManager(AsyncKernelManager):
    """``AsyncKernelManager`` over IPC (POSIX) whose shutdown sends no interrupt (see the module doc)."""

    @default("transport")
    def _transport_default(self) -> str:
        return "ipc" if os.name == "posix" else "tcp"

    @default("ip")
    def _ip_default(self) -> str:
        # jupyter_client names IPC sockets "kernel-ipc-<n>" in the working directory when no connection
        # file is set yet, so kernels started side by side from one folder could pick the same sockets
        # (the other kernel's messages then fail as "Invalid Signature"); each kernel gets its own folder
        if self.transport == "ipc":
            return os.path.join(tempfile.mkdtemp(prefix="ilocalg-kernel-"), "ipc")
        return super()._ip_default()

    async def _async_interrupt_kernel(self) -> None:
        if self.shutting_down:  # the run is over and the kernel idle: nothing to interrupt
            return
        await super()._async_interrupt_kernel()
