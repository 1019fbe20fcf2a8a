"""shroud.base.blas: the OpenBLAS pools of the process are held to one thread inside the block only."""

import numpy as np
import pytest

from shroud.base.blas import openblas_pools, single_threaded_blas


def test_every_pool_runs_one_thread_inside_and_its_own_count_after():
    np.ones((2, 2)) @ np.ones((2, 2))             # numpy's OpenBLAS is loaded
    pools = openblas_pools()
    if not pools:
        pytest.skip("no OpenBLAS found in this process (not Linux, or another BLAS)")
    before = [get() for get, _ in pools]
    with single_threaded_blas():
        assert [get() for get, _ in pools] == [1] * len(pools)
    assert [get() for get, _ in pools] == before


def test_the_count_comes_back_when_the_block_raises():
    pools = openblas_pools()
    before = [get() for get, _ in pools]
    with pytest.raises(RuntimeError), single_threaded_blas():
        raise RuntimeError("inside")
    assert [get() for get, _ in pools] == before
