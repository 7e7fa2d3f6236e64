// The process-wide transfer counters of core/Transfer.hpp. Layer: core.
#include <core/Transfer.hpp>

#include <atomic>

namespace mixcon {

namespace {
std::atomic<std::uint64_t> toHostCalls{0}, toHostBytes{0}, toDeviceCalls{0}, toDeviceBytes{0};
} // namespace

TransferCounts transferCounts() {
  TransferCounts c;
  c.toHostCalls = toHostCalls.load();
  c.toHostBytes = toHostBytes.load();
  c.toDeviceCalls = toDeviceCalls.load();
  c.toDeviceBytes = toDeviceBytes.load();
  return c;
}

void resetTransferCounts() {
  toHostCalls = 0;
  toHostBytes = 0;
  toDeviceCalls = 0;
  toDeviceBytes = 0;
}

namespace detail {
void countTransfer(bool toHost, std::size_t bytes) {
  if (toHost) {
    toHostCalls.fetch_add(1, std::memory_order_relaxed);
    toHostBytes.fetch_add(bytes, std::memory_order_relaxed);
  } else {
    toDeviceCalls.fetch_add(1, std::memory_order_relaxed);
    toDeviceBytes.fetch_add(bytes, std::memory_order_relaxed);
  }
}
} // namespace detail

} // namespace mixcon
