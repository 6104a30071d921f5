"""Evaluation 1: the kernel and streamline code that made session files of versions 1 and 2.

Kept unchanged so that those sessions replay bit for bit (``GreenKernel(..., evaluation=1)``,
which ``Sculptor.from_session`` picks for them); compiled only when such a kernel is used. New
work goes to the current evaluation (``gogreen_core._expansion``, ``gogreen_core._integrator``).
"""
