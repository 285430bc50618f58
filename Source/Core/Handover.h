#pragma once
// The hand-over of a prepared object (an engine, a set list's cues, a compiled mapping set) from
// the thread that builds it to the real-time thread that runs it, and of the object it replaces
// back to the builder to be deleted there — never on the real-time thread. One hand-over is in
// flight at a time: offer() refuses (and gives the object back) while the previous one has not
// been taken or the replaced object not collected, so the real-time side never waits, allocates
// or frees. The live rig's ControlLoop (engines), the plugin's Stage (set lists) and the mapping's
// Mapper (mapping sets) are its users (issue 32: they had three copies of it).
//
// Threads: builder side — offer(), canOffer(), collect(), newest(), and replace() while the
// real-time side is known not to run; real-time side — takeOffered(), active(). Lock-free: two
// atomic pointers.
#include <atomic>
#include <memory>

namespace armadillo::core {

template <typename T>
class Handover {
public:
    Handover() = default;
    Handover(const Handover&) = delete;
    Handover& operator=(const Handover&) = delete;
    ~Handover()
    {
        delete pending_.exchange(nullptr);
        delete retired_.exchange(nullptr);
        delete active_;
    }

    // Builder side ---------------------------------------------------------------------------
    /// Gives `next` to the real-time side, which takes it at its next takeOffered(). False, with
    /// `next` untouched, while an earlier object is still pending or a replaced one uncollected.
    bool offer(std::unique_ptr<T>& next) noexcept
    {
        if (!next || !canOffer()) return false;
        newest_ = next.get();
        pending_.store(next.release(), std::memory_order_release);
        return true;
    }
    bool canOffer() const noexcept
    {
        // pending first: once it reads empty, the hand-back stored before it is visible too.
        return pending_.load(std::memory_order_acquire) == nullptr && retired_.load(std::memory_order_acquire) == nullptr;
    }
    /// Deletes the object the real-time side gave up, if any.
    void collect() noexcept { delete retired_.exchange(nullptr, std::memory_order_acq_rel); }
    /// The object the real-time side gave up, if any, for the builder to keep (another thread may
    /// still read it: the builder decides when it is safe to delete).
    std::unique_ptr<T> takeRetired() noexcept { return std::unique_ptr<T>(retired_.exchange(nullptr, std::memory_order_acq_rel)); }
    /// Installs `next` at once, deleting whatever was active, pending or retired. Only while the
    /// real-time side is known not to run (its token held, or nothing runs yet).
    void replace(std::unique_ptr<T> next) noexcept
    {
        delete pending_.exchange(nullptr);
        delete retired_.exchange(nullptr);
        delete active_;
        active_ = next.release();
        newest_ = active_;
    }
    /// The builder's own record of what it last offered or installed (pending, else active): valid
    /// until its next collect() or replace(). Reading the real-time side's active pointer instead
    /// would race with its swap.
    T* newest() const noexcept { return newest_; }

    // Real-time side -------------------------------------------------------------------------
    /// Takes an offered object, if any: it becomes active(), `finish(old)` runs on the object it
    /// replaces (null when none was active) while that one is still the real-time side's, and only
    /// then is it handed back for collect() — so the builder cannot free it under `finish`.
    /// Returns whether a swap happened.
    ///
    /// The pending slot is emptied last: until then offer() refuses, so the builder cannot offer
    /// again between the take and the hand-back and have the next take overwrite an uncollected
    /// object (the three copies this replaced emptied it first and could leak one that way; the
    /// threaded test in Tests/Core/HandoverTests.cpp found it).
    template <typename Finish>
    bool takeOffered(Finish&& finish) noexcept
    {
        T* next = pending_.load(std::memory_order_acquire);
        if (next == nullptr) return false;
        T* old = active_;
        active_ = next;
        finish(old);
        retired_.store(old, std::memory_order_release);   // empty: offer() refuses while it is not
        pending_.store(nullptr, std::memory_order_release);
        return true;
    }
    bool takeOffered() noexcept
    {
        return takeOffered([](T*) noexcept {});
    }
    T* active() const noexcept { return active_; }

private:
    T* active_ = nullptr;                  // real-time side
    std::atomic<T*> pending_ {nullptr};
    std::atomic<T*> retired_ {nullptr};
    T* newest_ = nullptr;                  // builder side
};

} // namespace armadillo::core
