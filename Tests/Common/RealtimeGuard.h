#pragma once
// RealtimeGuard: proves that a piece of code (an audio callback) neither allocates nor locks
// (STYLE.md convention 5). It counts, per thread, calls of every global operator new/delete and
// of the pthread lock functions, and reports what happened between its construction and now.
//
// Usage. Every test source that wants a guard includes this header. EXACTLY ONE translation unit
// of each test executable defines the replacements (the C++ rule: a replaceable operator new is
// defined once per program), by writing
//
//     #define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
//     #include "Common/RealtimeGuard.h"
//
// Link the executable with ${CMAKE_DL_LIBS} (the lock counters find the real functions with
// dlsym). If no TU defines the implementation, RealtimeGuard::installed() is false and every
// count stays 0: a test must REQUIRE(RealtimeGuard::installed()) so it cannot pass vacuously.
//
//     RealtimeGuard guard;
//     scene.renderAudio(l, r, 64);
//     CHECK(guard.allocations() == 0);
//     CHECK(guard.locks() == 0);
//
// To find WHERE an allocation happens, construct the guard with RealtimeGuard::Mode::Trap: the
// first allocation, free or lock on this thread while it lives raises SIGTRAP, so a debugger
// stops at the offending call (without a debugger the test dies — use it while investigating).
//
// Counts are per thread (thread_local): a guard sees only what its own thread did, so other
// threads (the test framework, a control thread) cannot make it fail or pass. What it cannot
// see: malloc/free called directly, locks taken inside libc through internal symbols, and
// futex-based waits (std::atomic::wait). Locks are counted when code calls pthread_mutex_lock,
// pthread_mutex_trylock, pthread_rwlock_rdlock or pthread_rwlock_wrlock — which is what
// std::mutex, std::shared_mutex, std::lock_guard, function-local static guards under contention
// and most allocators do.
#include <atomic>
#include <cstdint>
#include <string>

namespace armadillo::test {

namespace realtime_detail {
struct Counters {
    std::uint64_t allocations = 0;
    std::uint64_t deallocations = 0;
    std::uint64_t locks = 0;
};
inline thread_local Counters threadCounters {};
inline thread_local int trapDepth = 0;   ///< > 0: a Trap-mode guard is alive on this thread
inline std::atomic<bool> implementationLinked {false};
} // namespace realtime_detail

class RealtimeGuard {
public:
    enum class Mode { Count, Trap };

    explicit RealtimeGuard(Mode mode = Mode::Count) noexcept : start_(realtime_detail::threadCounters), trap_(mode == Mode::Trap)
    {
        if (trap_) ++realtime_detail::trapDepth;
    }
    ~RealtimeGuard()
    {
        if (trap_) --realtime_detail::trapDepth;
    }
    RealtimeGuard(const RealtimeGuard&) = delete;
    RealtimeGuard& operator=(const RealtimeGuard&) = delete;

    /// True when some TU of this executable defined ARMADILLO_REALTIME_GUARD_IMPLEMENTATION.
    static bool installed() noexcept { return realtime_detail::implementationLinked.load(std::memory_order_relaxed); }

    /// operator new (every form) calls on this thread since construction (or restart()).
    std::uint64_t allocations() const noexcept { return now().allocations - start_.allocations; }
    /// operator delete (every form) calls with a non-null pointer since construction.
    std::uint64_t deallocations() const noexcept { return now().deallocations - start_.deallocations; }
    /// pthread lock calls on this thread since construction.
    std::uint64_t locks() const noexcept { return now().locks - start_.locks; }
    /// Nothing allocated, freed or locked.
    bool clean() const noexcept { return allocations() == 0 && deallocations() == 0 && locks() == 0; }
    void restart() noexcept { start_ = realtime_detail::threadCounters; }

    /// "allocations 0, deallocations 0, locks 0" (for failure messages; allocates, so call it
    /// after the guarded code).
    std::string report() const
    {
        return "allocations " + std::to_string(allocations()) + ", deallocations " + std::to_string(deallocations())
             + ", locks " + std::to_string(locks());
    }

private:
    static const realtime_detail::Counters& now() noexcept { return realtime_detail::threadCounters; }
    realtime_detail::Counters start_;
    bool trap_ = false;
};

} // namespace armadillo::test

#ifdef ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#ifndef ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#include <csignal>
#include <cstdlib>
#include <dlfcn.h>
#include <new>
#include <pthread.h>

namespace armadillo::test::realtime_detail {

/// A Trap-mode guard is alive: stop here (SIGTRAP), once, so the debugger shows the caller.
inline void violation() noexcept
{
    if (trapDepth > 0) {
        trapDepth = 0;   // trap once; the handler's own allocations must not trap again
        std::raise(SIGTRAP);
    }
}

inline void* allocate(std::size_t size)
{
    ++threadCounters.allocations;
    violation();
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}

inline void* allocateAligned(std::size_t size, std::align_val_t alignment)
{
    ++threadCounters.allocations;
    violation();
    const auto a = static_cast<std::size_t>(alignment);
    const std::size_t rounded = ((size ? size : 1) + a - 1) / a * a;   // aligned_alloc wants a multiple
    if (void* p = std::aligned_alloc(a, rounded)) return p;
    throw std::bad_alloc();
}

inline void release(void* p) noexcept
{
    if (!p) return;
    ++threadCounters.deallocations;
    violation();
    std::free(p);
}

struct Linked {
    Linked() noexcept { implementationLinked.store(true, std::memory_order_relaxed); }
};
inline const Linked linked {};

/// The next definition of a libc function (the one this file interposes), found once. A plain
/// atomic, not a function-local static: a static's guard could itself lock and recurse here.
template <typename Fn>
Fn realFunction(std::atomic<Fn>& cache, const char* name) noexcept
{
    Fn f = cache.load(std::memory_order_acquire);
    if (!f) {
        f = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, name));
        cache.store(f, std::memory_order_release);
    }
    return f;
}

} // namespace armadillo::test::realtime_detail

void* operator new(std::size_t size) { return armadillo::test::realtime_detail::allocate(size); }
void* operator new[](std::size_t size) { return armadillo::test::realtime_detail::allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
    try { return armadillo::test::realtime_detail::allocate(size); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
    try { return armadillo::test::realtime_detail::allocate(size); } catch (...) { return nullptr; }
}
void* operator new(std::size_t size, std::align_val_t a) { return armadillo::test::realtime_detail::allocateAligned(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return armadillo::test::realtime_detail::allocateAligned(size, a); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept
{
    try { return armadillo::test::realtime_detail::allocateAligned(size, a); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept
{
    try { return armadillo::test::realtime_detail::allocateAligned(size, a); } catch (...) { return nullptr; }
}
void operator delete(void* p) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete(void* p, std::size_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p, std::size_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete(void* p, std::align_val_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { armadillo::test::realtime_detail::release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { armadillo::test::realtime_detail::release(p); }

// Interposed lock functions: count, then call the C library's own.
namespace armadillo::test::realtime_detail {
using MutexFn = int (*)(pthread_mutex_t*);
using RwFn = int (*)(pthread_rwlock_t*);
inline std::atomic<MutexFn> realMutexLock {nullptr};
inline std::atomic<MutexFn> realMutexTryLock {nullptr};
inline std::atomic<RwFn> realRdLock {nullptr};
inline std::atomic<RwFn> realWrLock {nullptr};
} // namespace armadillo::test::realtime_detail

extern "C" int pthread_mutex_lock(pthread_mutex_t* m)
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.locks;
    violation();
    return realFunction(realMutexLock, "pthread_mutex_lock")(m);
}
extern "C" int pthread_mutex_trylock(pthread_mutex_t* m)
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.locks;
    violation();
    return realFunction(realMutexTryLock, "pthread_mutex_trylock")(m);
}
extern "C" int pthread_rwlock_rdlock(pthread_rwlock_t* l)
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.locks;
    violation();
    return realFunction(realRdLock, "pthread_rwlock_rdlock")(l);
}
extern "C" int pthread_rwlock_wrlock(pthread_rwlock_t* l)
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.locks;
    violation();
    return realFunction(realWrLock, "pthread_rwlock_wrlock")(l);
}
#endif // ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#endif // ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
