// Counted transfers between device views and host memory: every copy the library makes from a
// device View to the host (or back) goes through these functions, which count calls and bytes in
// a process-wide counter. A copy is counted whether or not the current backend's memory is
// host-accessible (under OpenMP the "copy" may be free, under CUDA it is a PCIe transfer), so a
// test that counts transfers means the same on every backend. Scalar results of reductions are
// not transfers. The bottom layer (core): every other layer may include it.
//
// Rule (checked by the test repo.transfer_api): solver/, contact/ and kernels/ make no raw host
// mirror copy (Kokkos::create_mirror_view*); they call these functions instead.
#pragma once

#include <Kokkos_Core.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace mixcon {

/// Calls and bytes moved since the last reset (host-side counters). The staging* counts are the
/// copies made inside a HostLibraryStaging scope, so that a host library (hypre built for the
/// CPU, Eigen) can read or write device-resident data: none where the memory is host-accessible
/// (hypre then works on the views in place), the right-hand side, solution and matrix values
/// per solve and setup under CUDA with a CPU hypre. The other counts are everything else.
struct TransferCounts {
  std::uint64_t toHostCalls = 0, toHostBytes = 0;
  std::uint64_t toDeviceCalls = 0, toDeviceBytes = 0;
  std::uint64_t stagingToHostCalls = 0, stagingToHostBytes = 0;
  std::uint64_t stagingToDeviceCalls = 0, stagingToDeviceBytes = 0;
};

namespace detail {
/// The process-wide counters: a static local of an inline function, one instance in the process
/// even with one shared library per layer (vague linkage; core stays header-only).
struct TransferCounters {
  std::atomic<std::uint64_t> toHostCalls{0}, toHostBytes{0}, toDeviceCalls{0}, toDeviceBytes{0};
  std::atomic<std::uint64_t> stagingToHostCalls{0}, stagingToHostBytes{0},
      stagingToDeviceCalls{0}, stagingToDeviceBytes{0};
};
inline TransferCounters &transferCounters() {
  static TransferCounters counters;
  return counters;
}

/// How many HostLibraryStaging scopes the calling thread is in.
inline int &stagingDepth() {
  static thread_local int depth = 0;
  return depth;
}

inline void countTransfer(bool toHost, std::size_t bytes) {
  TransferCounters &c = transferCounters();
  const bool staging = stagingDepth() > 0;
  auto &calls = staging ? (toHost ? c.stagingToHostCalls : c.stagingToDeviceCalls)
                        : (toHost ? c.toHostCalls : c.toDeviceCalls);
  auto &moved = staging ? (toHost ? c.stagingToHostBytes : c.stagingToDeviceBytes)
                        : (toHost ? c.toHostBytes : c.toDeviceBytes);
  calls.fetch_add(1, std::memory_order_relaxed);
  moved.fetch_add(bytes, std::memory_order_relaxed);
}

template <class V> std::size_t viewBytes(const V &v) {
  return v.span() * sizeof(typename V::value_type);
}
} // namespace detail

/// The counts accumulated by this process since start or the last resetTransferCounts().
inline TransferCounts transferCounts() {
  const detail::TransferCounters &c = detail::transferCounters();
  TransferCounts t;
  t.toHostCalls = c.toHostCalls.load();
  t.toHostBytes = c.toHostBytes.load();
  t.toDeviceCalls = c.toDeviceCalls.load();
  t.toDeviceBytes = c.toDeviceBytes.load();
  t.stagingToHostCalls = c.stagingToHostCalls.load();
  t.stagingToHostBytes = c.stagingToHostBytes.load();
  t.stagingToDeviceCalls = c.stagingToDeviceCalls.load();
  t.stagingToDeviceBytes = c.stagingToDeviceBytes.load();
  return t;
}

inline void resetTransferCounts() {
  detail::TransferCounters &c = detail::transferCounters();
  for (auto *n : {&c.toHostCalls, &c.toHostBytes, &c.toDeviceCalls, &c.toDeviceBytes,
                  &c.stagingToHostCalls, &c.stagingToHostBytes, &c.stagingToDeviceCalls,
                  &c.stagingToDeviceBytes})
    *n = 0;
}

/// While one is alive, the calling thread's transfers count as staging for a host library
/// (TransferCounts::staging*): the solver wrappers around hypre and Eigen open one.
class HostLibraryStaging {
public:
  HostLibraryStaging() { ++detail::stagingDepth(); }
  ~HostLibraryStaging() { --detail::stagingDepth(); }
  HostLibraryStaging(const HostLibraryStaging &) = delete;
  HostLibraryStaging &operator=(const HostLibraryStaging &) = delete;
};

/// A host copy of `v` (its HostSpace mirror, filled). Counted device -> host.
template <class V> auto copyToHost(const V &v) {
  detail::countTransfer(true, detail::viewBytes(v));
  return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
}

/// A host copy of a view of rank 1 to 3 as a std::vector, its entries in row-major order
/// (v(i, j, k) at (i * extent(1) + j) * extent(2) + k) whatever the view's layout: CUDA's default
/// LayoutLeft stores them column-major, so the copy's raw memory is not that order. Counted
/// device -> host.
template <class V>
std::vector<std::remove_const_t<typename V::value_type>> toHostVector(const V &v) {
  static_assert(V::rank >= 1 && V::rank <= 3, "toHostVector takes a view of rank 1 to 3");
  const auto h = copyToHost(v);
  std::vector<std::remove_const_t<typename V::value_type>> out(h.size());
  std::size_t at = 0;
  if constexpr (V::rank == 1) {
    for (std::size_t i = 0; i < h.extent(0); ++i)
      out[at++] = h(i);
  } else if constexpr (V::rank == 2) {
    for (std::size_t i = 0; i < h.extent(0); ++i)
      for (std::size_t j = 0; j < h.extent(1); ++j)
        out[at++] = h(i, j);
  } else {
    for (std::size_t i = 0; i < h.extent(0); ++i)
      for (std::size_t j = 0; j < h.extent(1); ++j)
        for (std::size_t k = 0; k < h.extent(2); ++k)
          out[at++] = h(i, j, k);
  }
  return out;
}

/// A host mirror of `v` to fill and send with copyToDevice (no copy, not counted). Its contents
/// are unspecified; on a host-accessible space it may alias `v`.
template <class V> auto hostMirror(const V &v) { return Kokkos::create_mirror_view(v); }

/// Device view `dst` = host view `src` (same shape). Counted host -> device.
template <class D, class H> void copyToDevice(const D &dst, const H &src) {
  detail::countTransfer(false, detail::viewBytes(dst));
  Kokkos::deep_copy(dst, src);
}

/// Device view `dst` = the values of `src` (dst.size() entries). Counted host -> device.
template <class D, class T> void copyToDevice(const D &dst, const std::vector<T> &src) {
  static_assert(D::rank == 1, "copyToDevice from a std::vector takes a rank-1 view");
  auto m = hostMirror(dst);
  for (std::size_t i = 0; i < m.extent(0); ++i)
    m(i) = src[i];
  copyToDevice(dst, m);
}

/// Host view `dst` = device view `src` (same shape). Counted device -> host.
template <class H, class D> void copyToHost(const H &dst, const D &src) {
  detail::countTransfer(true, detail::viewBytes(src));
  Kokkos::deep_copy(dst, src);
}

/// A range of the host's threads (the setup's loops over host data: graphs, maps, copies).
using HostRange = Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>;

/// True where host code may read and write the memory of views in `Space` directly (OpenMP,
/// Serial, CUDA UVM), so a host library such as hypre can work on their memory without a copy.
template <class Space>
inline constexpr bool kHostAccessible =
    Kokkos::SpaceAccessibility<Kokkos::HostSpace, Space>::accessible;

/// A view host code can read: `v` itself where its memory is host-accessible (no copy on any
/// backend where this branch is taken, so nothing is counted), else a counted host copy. For host
/// libraries (hypre on the CPU, Eigen) that read device-resident data inside solver loops.
template <class V> auto hostReadable(const V &v) {
  if constexpr (kHostAccessible<typename V::memory_space>)
    return v;
  else
    return copyToHost(v);
}

} // namespace mixcon
