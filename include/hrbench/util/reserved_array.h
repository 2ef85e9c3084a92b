// An array that grows in place: where that costs nothing, its address space is reserved
// up front for the most elements it may hold, and the system backs it with memory page
// by page as it fills. A std::vector grown by doubling holds the old and the new block
// at once, and copies the one into the other; a forest growing to its memory budget then
// peaks at twice its size. Here growth within the reservation moves nothing, and only
// touched pages count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>

namespace hrbench {

// Address space for _bytes_, page-aligned, backed with zeroed memory on first touch and
// not counted against the system's commit limit where it can be avoided; nullptr if the
// system refuses. Bytes are rounded up to whole pages (PageRoundUp()).
void *MapAddressSpace(size_t bytes);
void UnmapAddressSpace(void *address, size_t bytes);
size_t PageRoundUp(size_t bytes);
// Backs the pages that hold [begin, end), all of it mapped, with memory now: one system
// call, where touching them one by one takes a fault each. What they hold is unchanged.
// Returns false, doing nothing, where the system cannot (before Linux 5.14; elsewhere).
bool PopulateAddressSpace(const void *begin, const void *end);
// Gives the whole pages within [begin, end) back to the system: they read as zero
// afterwards. The partial pages at either end are kept, and so is the mapping.
void DiscardAddressSpace(const void *begin, const void *end);

// Whether address space reserved beyond what is used costs nothing here: the process's
// address space is not limited (RLIMIT_AS) and the system does not charge reservations
// against a commit limit (Linux, vm.overcommit_memory other than 2). Elsewhere a
// reservation for a whole memory budget would take what other arrays, and threads'
// stacks, need.
bool ReservationsAreFree();

template <typename T>
class ReservedArray {
  public:
    ReservedArray() = default;
    ReservedArray(const ReservedArray &other) {
        ReserveUpFront(other.capacity_);
        Reserve(other.size_);
        std::uninitialized_copy(other.begin(), other.end(), data_);
        size_ = other.size_;
    }
    ReservedArray(ReservedArray &&other) noexcept { Swap(other); }
    ReservedArray &operator=(ReservedArray other) noexcept {
        Swap(other);
        return *this;
    }
    ~ReservedArray() { Release(); }

    // Makes room for _n_ elements in all; throws std::bad_alloc if the system refuses.
    // Moves the elements (as std::vector does) only if _n_ exceeds the reservation.
    void Reserve(size_t n) {
        if (n > capacity_ && !Relocate(n))
            throw std::bad_alloc();
    }

    // Reserves room for _n_ elements where reservations are free (ReservationsAreFree())
    // and the system grants it; otherwise changes nothing, and the array grows by
    // doubling, as std::vector does. For a caller that knows the most it may need,
    // which is often far more than it uses.
    void ReserveUpFront(size_t n) {
        if (n > capacity_ && ReservationsAreFree())
            Relocate(n);
    }

    void push_back(const T &value) {
        if (size_ == capacity_)
            Reserve(std::max<size_t>(2 * capacity_, 1));
        new (data_ + size_) T(value);
        ++size_;
    }

    size_t size() const { return size_; }
    size_t capacity() const { return capacity_; }
    bool empty() const { return size_ == 0; }
    T &operator[](size_t k) { return data_[k]; }
    const T &operator[](size_t k) const { return data_[k]; }
    T *begin() { return data_; }
    T *end() { return data_ + size_; }
    const T *begin() const { return data_; }
    const T *end() const { return data_ + size_; }

  private:
    // Moves the elements into a new reservation for _n_ > capacity_ elements (whole
    // pages of them); false, changing nothing, if the system refuses.
    bool Relocate(size_t n) {
        if (n > SIZE_MAX / sizeof(T) / 2)
            return false;
        size_t bytes = PageRoundUp(n * sizeof(T));
        T *grown = static_cast<T *>(MapAddressSpace(bytes));
        if (!grown)
            return false;
        std::uninitialized_move(begin(), end(), grown);
        size_t size = size_;
        Release();
        data_ = grown, size_ = size, capacity_ = bytes / sizeof(T);
        return true;
    }

    void Release() {
        if (!data_)
            return;
        std::destroy(begin(), end());
        UnmapAddressSpace(data_, capacity_ * sizeof(T));
        data_ = nullptr, size_ = capacity_ = 0;
    }

    void Swap(ReservedArray &other) noexcept {
        std::swap(data_, other.data_);
        std::swap(size_, other.size_);
        std::swap(capacity_, other.capacity_);
    }

    T *data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};

}  // namespace hrbench
