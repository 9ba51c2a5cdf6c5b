// aaeval.native.samplers_testing: the samplers' inner pieces bound for the tests alone
// (tests/native/test_samplers_native.py).
#include <nanobind/nanobind.h>

#include <cstdint>

#include "samplers/sampling.hpp"

namespace nb = nanobind;

NB_MODULE(samplers_testing, m) {
    m.doc() = "The point samplers' inner pieces, for the tests";
    m.def("jitter_uniform", &aaeval::samplers::jitter_uniform, nb::arg("seed"), nb::arg("row"), nb::arg("col"),
          nb::arg("sample"), nb::arg("axis"), "A uniform number in [0, 1) fixed by (seed, row, col, sample, axis).");
}
