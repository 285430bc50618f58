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
// threads (the test framework, a control thread) cannot make it fail or pass. It sees: every
// operator new/delete form (plain, array, sized, aligned, nothrow); malloc, calloc, realloc,
// free, aligned_alloc, posix_memalign, memalign; pthread_mutex_lock/trylock and
// pthread_rwlock_rdlock/wrlock (what std::mutex, std::shared_mutex, contended static guards and
// most allocators call); and every throw (__cxa_allocate_exception and __cxa_throw). It cannot
// see locks taken inside libc through internal symbols or futex waits (std::atomic::wait).
//
// Sanitizer builds (ASan, TSan) own malloc and operator new themselves: there the replacements
// are left out, installed() is false, and guard tests say so and stop (ARMADILLO_GUARD_UNDER_SANITIZER).
#include <atomic>
#include <cstdint>
#include <string>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ARMADILLO_GUARD_UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define ARMADILLO_GUARD_UNDER_SANITIZER 1
#endif
#endif

namespace armadillo::test {

namespace realtime_detail {
struct Counters {
    std::uint64_t allocations = 0;
    std::uint64_t deallocations = 0;
    std::uint64_t locks = 0;
    std::uint64_t throws = 0;
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

    /// operator new (every form) and malloc-family calls on this thread since construction (or restart()).
    std::uint64_t allocations() const noexcept { return now().allocations - start_.allocations; }
    /// operator delete (every form) and free() calls with a non-null pointer since construction.
    std::uint64_t deallocations() const noexcept { return now().deallocations - start_.deallocations; }
    /// pthread lock calls on this thread since construction.
    std::uint64_t locks() const noexcept { return now().locks - start_.locks; }
    /// Exceptions thrown on this thread since construction (caught or not).
    std::uint64_t throws() const noexcept { return now().throws - start_.throws; }
    /// Nothing allocated, freed, locked or thrown.
    bool clean() const noexcept { return allocations() == 0 && deallocations() == 0 && locks() == 0 && throws() == 0; }
    void restart() noexcept { start_ = realtime_detail::threadCounters; }

    /// "allocations 0, deallocations 0, locks 0" (for failure messages; allocates, so call it
    /// after the guarded code).
    std::string report() const
    {
        return "allocations " + std::to_string(allocations()) + ", deallocations " + std::to_string(deallocations())
             + ", locks " + std::to_string(locks()) + ", throws " + std::to_string(throws());
    }

private:
    static const realtime_detail::Counters& now() noexcept { return realtime_detail::threadCounters; }
    realtime_detail::Counters start_;
    bool trap_ = false;
};

} // namespace armadillo::test

#if defined(ARMADILLO_REALTIME_GUARD_IMPLEMENTATION) && !defined(ARMADILLO_GUARD_UNDER_SANITIZER)
#ifndef ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <new>
#include <pthread.h>
#include <cxxabi.h>
#include <typeinfo>

// glibc's own allocator entry points: the replacements below count, then call these (no dlsym,
// which could itself allocate and recurse).
extern "C" {
void* __libc_malloc(std::size_t) noexcept;
void* __libc_calloc(std::size_t, std::size_t) noexcept;
void* __libc_realloc(void*, std::size_t) noexcept;
void __libc_free(void*) noexcept;
void* __libc_memalign(std::size_t, std::size_t) noexcept;
}

namespace armadillo::test::realtime_detail {

/// A Trap-mode guard is alive: stop here (SIGTRAP), once, so the debugger shows the caller.
inline void violation() noexcept
{
    if (trapDepth > 0) {
        trapDepth = 0;   // trap once; the handler's own allocations must not trap again
        std::raise(SIGTRAP);
    }
}

inline void* countedMalloc(std::size_t size) noexcept
{
    ++threadCounters.allocations;
    violation();
    return __libc_malloc(size);
}

inline void* countedMemalign(std::size_t alignment, std::size_t size) noexcept
{
    ++threadCounters.allocations;
    violation();
    return __libc_memalign(alignment, size);
}

inline void countedFree(void* p) noexcept
{
    if (!p) return;
    ++threadCounters.deallocations;
    violation();
    __libc_free(p);
}

inline void* allocate(std::size_t size)
{
    if (void* p = countedMalloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}

inline void* allocateAligned(std::size_t size, std::align_val_t alignment)
{
    const auto a = static_cast<std::size_t>(alignment);
    if (void* p = countedMemalign(a, size ? size : 1)) return p;
    throw std::bad_alloc();
}

inline void release(void* p) noexcept { countedFree(p); }

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

// The C allocator: code that calls malloc/free directly (C libraries, Eigen's aligned_malloc).
extern "C" void* malloc(std::size_t size) noexcept { return armadillo::test::realtime_detail::countedMalloc(size); }
extern "C" void free(void* p) noexcept { armadillo::test::realtime_detail::countedFree(p); }
extern "C" void* calloc(std::size_t n, std::size_t size) noexcept
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.allocations;
    violation();
    return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t size) noexcept
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.allocations;   // grows, moves or frees: any of them is heap work
    violation();
    return __libc_realloc(p, size);
}
extern "C" void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept
{
    return armadillo::test::realtime_detail::countedMemalign(alignment, size);
}
extern "C" void* memalign(std::size_t alignment, std::size_t size) noexcept
{
    return armadillo::test::realtime_detail::countedMemalign(alignment, size);
}
extern "C" int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept
{
    if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) return 22;   // EINVAL
    void* p = armadillo::test::realtime_detail::countedMemalign(alignment, size);
    if (!p) return 12;   // ENOMEM
    *out = p;
    return 0;
}

void* operator new(std::size_t size) { return armadillo::test::realtime_detail::allocate(size); }
void* operator new[](std::size_t size) { return armadillo::test::realtime_detail::allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
    return armadillo::test::realtime_detail::countedMalloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
    return armadillo::test::realtime_detail::countedMalloc(size ? size : 1);
}
void* operator new(std::size_t size, std::align_val_t a) { return armadillo::test::realtime_detail::allocateAligned(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return armadillo::test::realtime_detail::allocateAligned(size, a); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept
{
    return armadillo::test::realtime_detail::countedMemalign(static_cast<std::size_t>(a), size ? size : 1);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept
{
    return armadillo::test::realtime_detail::countedMemalign(static_cast<std::size_t>(a), size ? size : 1);
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

// Interposed lock and throw functions: count, then call the C/C++ runtime's own.
namespace armadillo::test::realtime_detail {
using MutexFn = int (*)(pthread_mutex_t*);
using RwFn = int (*)(pthread_rwlock_t*);
using AllocateExceptionFn = void* (*)(std::size_t);
using ThrowFn = void (*)(void*, std::type_info*, void (*)(void*));
inline std::atomic<MutexFn> realMutexLock {nullptr};
inline std::atomic<MutexFn> realMutexTryLock {nullptr};
inline std::atomic<RwFn> realRdLock {nullptr};
inline std::atomic<RwFn> realWrLock {nullptr};
inline std::atomic<AllocateExceptionFn> realAllocateException {nullptr};
inline std::atomic<ThrowFn> realThrow {nullptr};
inline thread_local bool inThrow = false;   ///< __cxa_throw follows __cxa_allocate_exception: one throw
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
// Every `throw` first allocates its exception object, then throws it: both are counted as one
// throw (a rethrow of a caught exception reaches only __cxa_rethrow and is not counted). Defined
// with the C++ runtime's own declarations (cxxabi.h), in its namespace.
namespace __cxxabiv1 {
extern "C" void* __cxa_allocate_exception(std::size_t size) _GLIBCXX_NOTHROW
{
    using namespace armadillo::test::realtime_detail;
    ++threadCounters.throws;
    inThrow = true;
    violation();
    return realFunction(realAllocateException, "__cxa_allocate_exception")(size);
}
extern "C" void __cxa_throw(void* object, std::type_info* type, void (_GLIBCXX_CDTOR_CALLABI* destructor)(void*))
{
    using namespace armadillo::test::realtime_detail;
    if (!inThrow) ++threadCounters.throws;   // an exception object made some other way
    inThrow = false;
    violation();
    realFunction(realThrow, "__cxa_throw")(object, type, destructor);
    std::abort();   // __cxa_throw does not return
}
} // namespace __cxxabiv1
#endif // ARMADILLO_REALTIME_GUARD_IMPLEMENTED
#endif // ARMADILLO_REALTIME_GUARD_IMPLEMENTATION

// In a Catch2 test case (catch.hpp included first): the guard must be there before a test trusts a
// zero from it. Under a sanitizer build it is left out: the test says so and ends as passed (the
// normal build runs it; the sanitizer run is about memory and threads, not about this count).
#ifdef ARMADILLO_GUARD_UNDER_SANITIZER
#define ARMADILLO_REQUIRE_GUARD()                                                                  \
    do {                                                                                           \
        WARN("sanitizer build: the real-time guard is left out; the normal build runs this check"); \
        SUCCEED("skipped under the sanitizer");                                                    \
        return;                                                                                    \
    } while (false)
#else
#define ARMADILLO_REQUIRE_GUARD() REQUIRE(::armadillo::test::RealtimeGuard::installed())
#endif

// The guard installed (or the test stops under a sanitizer, as above), then proved on this
// thread: a probe sees an allocation before any zero it counts is trusted.
#define ARMADILLO_REQUIRE_GUARD_SEES_ALLOCATION()                                                  \
    ARMADILLO_REQUIRE_GUARD();                                                                     \
    do {                                                                                           \
        ::armadillo::test::RealtimeGuard armadilloProbe;                                           \
        int* volatile armadilloProbed = new int(1);                                                \
        CHECK(armadilloProbe.allocations() >= 1);                                                  \
        delete armadilloProbed;                                                                    \
    } while (false)
