#include "hrbench/util/reserved_array.h"

#include <cstdlib>
#include <fstream>

#if defined(__unix__)
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace hrbench {

namespace {

uintptr_t PageSize() {
#if defined(__unix__)
    static const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
    return page;
#else
    return 4096;
#endif
}

uintptr_t PageDown(const void *address) {
    return reinterpret_cast<uintptr_t>(address) / PageSize() * PageSize();
}

uintptr_t PageUp(const void *address) {
    return (reinterpret_cast<uintptr_t>(address) + PageSize() - 1) / PageSize() * PageSize();
}

}  // namespace

size_t PageRoundUp(size_t bytes) { return (bytes + PageSize() - 1) / PageSize() * PageSize(); }

bool ReservationsAreFree() {
#if defined(__linux__)
    static const bool free = [] {
        struct rlimit limit;
        if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur != RLIM_INFINITY)
            return false;
        std::ifstream policy("/proc/sys/vm/overcommit_memory");
        int mode = 2;
        return bool(policy >> mode) && mode != 2;
    }();
    return free;
#else
    return false;
#endif
}

void *MapAddressSpace(size_t bytes) {
    bytes = PageRoundUp(bytes);
#if defined(__unix__)
    // MAP_NORESERVE: a reservation far beyond what is used is not charged against the
    // commit limit (except under strict overcommit, where none is made up front).
    void *address = mmap(nullptr, bytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    return address == MAP_FAILED ? nullptr : address;
#else
    return std::calloc(bytes, 1);
#endif
}

bool PopulateAddressSpace(const void *begin, const void *end) {
#if defined(MADV_POPULATE_WRITE)
    uintptr_t first = PageDown(begin), last = PageUp(end);  // outward: every page touched
    return last <= first ||
           madvise(reinterpret_cast<void *>(first), last - first, MADV_POPULATE_WRITE) == 0;
#else
    (void)begin, (void)end;
    return false;
#endif
}

void DiscardAddressSpace(const void *begin, const void *end) {
#if defined(__unix__)
    uintptr_t first = PageUp(begin), last = PageDown(end);  // inward: whole pages only
    if (last > first)
        madvise(reinterpret_cast<void *>(first), last - first, MADV_DONTNEED);
#else
    (void)begin, (void)end;
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
