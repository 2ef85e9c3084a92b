#include "hrbench/util/reserved_array.h"

#include <cstdlib>

#if defined(__unix__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace hrbench {

size_t PageRoundUp(size_t bytes) {
#if defined(__unix__)
    static const size_t page = size_t(sysconf(_SC_PAGESIZE));
#else
    constexpr size_t page = 4096;
#endif
    return (bytes + page - 1) / page * page;
}

void *MapAddressSpace(size_t bytes) {
    bytes = PageRoundUp(bytes);
#if defined(__unix__)
    // MAP_NORESERVE: a reservation far beyond what is used is not charged against the
    // commit limit (under strict overcommit it is, and a refusal makes the caller
    // reserve less).
    void *address = mmap(nullptr, bytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    return address == MAP_FAILED ? nullptr : address;
#else
    return std::calloc(bytes, 1);
#endif
}

void UnmapAddressSpace(void *address, size_t bytes) {
#if defined(__unix__)
    munmap(address, PageRoundUp(bytes));
#else
    (void)bytes;
    std::free(address);
#endif
}

}  // namespace hrbench
