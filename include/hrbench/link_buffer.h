// Storage for links: a growable array of trivially copyable 8-byte records.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>

#include "hrbench/util/reserved_array.h"

namespace hrbench {

// One stored link: two element indices, 8 bytes.
struct Link {
    uint32_t i, j;
};

// Like std::vector<Link>, without what costs most at 1e8 links: growth uses realloc,
// which moves large blocks by remapping pages instead of copying them, and appending
// after Reserve() is a plain store (std::vector's out-of-line growth path kept its
// push_back from being inlined into the refinement kernel).
class LinkBuffer {
  public:
    static_assert(std::is_trivially_copyable_v<Link>);

    LinkBuffer() = default;
    LinkBuffer(LinkBuffer &&other) noexcept { Swap(other); }
    LinkBuffer &operator=(LinkBuffer &&other) noexcept {
        LinkBuffer(std::move(other)).Swap(*this);
        return *this;
    }
    LinkBuffer(const LinkBuffer &) = delete;
    LinkBuffer &operator=(const LinkBuffer &) = delete;
    ~LinkBuffer() { std::free(data_); }

    // Makes room for _capacity_ links in all; throws std::bad_alloc if memory runs out.
    void Reserve(size_t capacity) {
        if (capacity <= capacity_)
            return;
        void *grown = std::realloc(data_, capacity * sizeof(Link));
        if (!grown)
            throw std::bad_alloc();
        data_ = static_cast<Link *>(grown);
        capacity_ = capacity;
    }

    // Returns unused capacity to the system (realloc shrinks in place).
    void ShrinkToFit() {
        if (size_ == capacity_)
            return;
        if (size_ == 0) {
            std::free(data_);
            data_ = nullptr;
        } else if (void *shrunk = std::realloc(data_, size_ * sizeof(Link))) {
            data_ = static_cast<Link *>(shrunk);
        } else {
            return;  // keep the larger block
        }
        capacity_ = size_;
    }

    // Gives the whole memory pages among links [begin, end) back to the system; their
    // values are lost (they read as zero), the rest of the buffer is unchanged. For a
    // caller that has copied those links elsewhere and never reads them again, so that
    // the copy and the original together hold little more than one of them.
    void Discard(size_t begin, size_t end) {
        DiscardAddressSpace(data_ + begin, data_ + std::min(end, size_));
    }

    // Backs links [begin, end) (within the capacity) with memory now, in one system
    // call, where appending them would fault a page at a time; false where the system
    // cannot (PopulateAddressSpace()).
    bool Populate(size_t begin, size_t end) {
        return PopulateAddressSpace(data_ + begin, data_ + end);
    }

    // Sets the size to _n_ <= capacity(), leaving any new links unwritten: for a caller
    // that fills them all, in any order (on several threads, each its own range).
    void Resize(size_t n) { size_ = n; }

    // Appends a link; the caller has made room (size() < capacity()).
    void Append(Link link) { data_[size_++] = link; }

    size_t size() const { return size_; }
    size_t capacity() const { return capacity_; }
    bool empty() const { return size_ == 0; }
    Link &operator[](size_t k) { return data_[k]; }
    const Link &operator[](size_t k) const { return data_[k]; }
    Link *begin() { return data_; }
    Link *end() { return data_ + size_; }
    const Link *begin() const { return data_; }
    const Link *end() const { return data_ + size_; }

  private:
    void Swap(LinkBuffer &other) noexcept {
        std::swap(data_, other.data_);
        std::swap(size_, other.size_);
        std::swap(capacity_, other.capacity_);
    }

    Link *data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};

}  // namespace hrbench
