# The GIL is released while the kernels run: two Python threads calling warp on large frames are
# inside the library at the same time. Proved with the module's test-only counter of calls inside
# the GIL-released region, not with timings: with a rendezvous armed, each call waits there (at
# most 60 s) until both are in; had the GIL been held, the second thread could not enter, the
# first would time out and the counter would say 1.
import threading

import numpy as np

import reproject


def test_two_threads_are_inside_the_library_at_once():
    height, width = 1080, 1920
    rng = np.random.default_rng(3)
    color = rng.random((3, height, width), dtype=np.float32)
    depth = rng.random((height, width), dtype=np.float32) * np.float32(0.9)
    errors, results = [], {}

    def call(name):
        try:
            results[name] = reproject.warp(color, depth, encoding="standard", near=1.0, far=20.0, convergence=3.5,
                                           threads=1)
        except Exception as e:  # reported by the assertion below
            errors.append(e)

    reproject._debug_reset_counters(rendezvous=2, timeout_seconds=60.0)
    try:
        threads = [threading.Thread(target=call, args=(name,)) for name in ("a", "b")]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        overlap = reproject._debug_max_concurrent_calls()
    finally:
        reproject._debug_reset_counters()
    assert not errors, errors
    print(f"calls inside the library at once: {overlap}")
    assert overlap == 2
    assert np.array_equal(results["a"].color, results["b"].color)


def test_counter_sees_one_call_at_a_time_from_one_thread():
    rng = np.random.default_rng(4)
    color = rng.random((3, 64, 64), dtype=np.float32)
    depth = rng.random((64, 64), dtype=np.float32)
    reproject._debug_reset_counters()
    for _ in range(3):
        reproject.warp(color, depth, encoding="standard", near=1.0, far=20.0, convergence=3.5)
    assert reproject._debug_max_concurrent_calls() == 1
