#pragma once
// Fixed-capacity single-producer / single-consumer queue: the only way data crosses from the
// device/control thread to the audio thread (STYLE.md convention 5). No locks, no allocation
// after construction; push fails (returns false) when full instead of blocking.
#include <array>
#include <atomic>
#include <cstddef>
#include <thread>
#include <type_traits>

namespace armadillo::core {

template <typename U> struct SeqLockProbe;

template <typename T, std::size_t Capacity>
class SpscQueue {
    static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "capacity must be a power of two");
    static_assert(std::is_trivially_copyable_v<T>, "elements are copied without locks");

public:
    bool push(const T& value) noexcept
    {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) == Capacity) return false;
        slots_[head & (Capacity - 1)] = value;
        head_.store(head + 1, std::memory_order_release);
        return true;
    }

    bool pop(T& out) noexcept
    {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (head_.load(std::memory_order_acquire) == tail) return false;
        out = slots_[tail & (Capacity - 1)];
        tail_.store(tail + 1, std::memory_order_release);
        return true;
    }

    /// Consumer only: a copy of the oldest element without taking it; false when empty.
    bool peek(T& out) const noexcept
    {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (head_.load(std::memory_order_acquire) == tail) return false;
        out = slots_[tail & (Capacity - 1)];
        return true;
    }

    std::size_t size() const noexcept
    {
        return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
    }
    static constexpr std::size_t capacity() noexcept { return Capacity; }

private:
    std::array<T, Capacity> slots_ {};
    alignas(64) std::atomic<std::size_t> head_ {0};
    alignas(64) std::atomic<std::size_t> tail_ {0};
};

/// Latest-value mailbox for one writer and any number of readers (a seqlock). Readers never
/// block the writer. A read that overlaps a write is retried, at most kMaxAttempts times, so a
/// writer pre-empted in the middle of a store cannot stall a real-time reader: real-time readers
/// call tryLoad() or load(lastGood) and keep their last good value when every attempt overlapped.
template <typename T>
class SeqLock {
    static_assert(std::is_trivially_copyable_v<T>, "values are copied without locks");

public:
    static constexpr int kMaxAttempts = 64;

    void store(const T& value) noexcept
    {
        const unsigned s = sequence_.load(std::memory_order_relaxed);
        sequence_.store(s + 1, std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_release);
        copyIn(value);
        std::atomic_thread_fence(std::memory_order_release);
        sequence_.store(s + 2, std::memory_order_release);
    }

    /// Real-time: a consistent copy of the latest value into `out` within kMaxAttempts reads;
    /// false (and `out` untouched) when a write overlapped every one of them.
    bool tryLoad(T& out) const noexcept
    {
        for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
            const unsigned before = sequence_.load(std::memory_order_acquire);
            if (before & 1u) continue;
            T copy;
            copyOut(copy);
            std::atomic_thread_fence(std::memory_order_acquire);
            if (sequence_.load(std::memory_order_relaxed) == before) {
                out = copy;
                return true;
            }
        }
        return false;
    }

    /// Real-time: the latest value, or `lastGood` (the caller's previous result) when a write
    /// overlapped every attempt.
    T load(const T& lastGood) const noexcept
    {
        T out = lastGood;
        tryLoad(out);
        return out;
    }

    /// Not for the audio thread: yields between bounded attempts until a consistent value is
    /// read (message/UI threads, link threads that can afford to wait for a pre-empted writer).
    T load() const noexcept
    {
        T out {};
        while (!tryLoad(out)) std::this_thread::yield();
        return out;
    }

private:
    template <typename U> friend struct SeqLockProbe;   // tests: hold a write open
    // Word-wise relaxed atomics keep the copy free of data races in the memory model.
    static constexpr std::size_t kWords = (sizeof(T) + sizeof(unsigned long) - 1) / sizeof(unsigned long);
    void copyIn(const T& v) noexcept
    {
        unsigned long buf[kWords] {};
        __builtin_memcpy(buf, &v, sizeof(T));
        for (std::size_t i = 0; i < kWords; ++i) words_[i].store(buf[i], std::memory_order_relaxed);
    }
    void copyOut(T& v) const noexcept
    {
        unsigned long buf[kWords];
        for (std::size_t i = 0; i < kWords; ++i) buf[i] = words_[i].load(std::memory_order_relaxed);
        __builtin_memcpy(&v, buf, sizeof(T));
    }
    std::atomic<unsigned> sequence_ {0};
    std::array<std::atomic<unsigned long>, kWords> words_ {};
};

} // namespace armadillo::core
