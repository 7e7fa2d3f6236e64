// Portability shims between Kokkos 3.4 (Debian's trilinos sources) and Kokkos 4.x.
// The bottom layer (core): every other layer may include it; it includes only Kokkos.
#pragma once

#include <Kokkos_Core.hpp>

namespace mixcon {

/// Unsigned 64-bit offsets into CSR value arrays (3D meshes overflow 32-bit nonzero counts).
using Offset = std::int64_t;
/// Local (on-rank) indices of nodes, dofs and elements.
using LocalIndex = int;

namespace detail {
#if KOKKOS_VERSION >= 30700
using Kokkos::atan2;
using Kokkos::cos;
using Kokkos::fabs;
using Kokkos::sin;
using Kokkos::sqrt;
#else
using Kokkos::Experimental::atan2;
using Kokkos::Experimental::cos;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::sin;
using Kokkos::Experimental::sqrt;
#endif
} // namespace detail

} // namespace mixcon
