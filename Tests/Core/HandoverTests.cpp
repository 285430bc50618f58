// Core/Handover.h: the one hand-over of prepared objects to the real-time side (engines, set
// lists, mapping sets). One in flight at a time; the replaced object is deleted by the builder,
// never by the real-time thread; nothing leaks, whatever the interleaving.
#include "Core/Handover.h"
#include <catch2/catch.hpp>
#include <atomic>
#include <chrono>
#include <thread>

using namespace armadillo;
using namespace armadillo::core;

namespace {

std::atomic<int> gAlive {0};
std::atomic<int> gDeletedOnRealtime {0};
thread_local bool tRealtime = false;

struct Thing {
    explicit Thing(int v) : value(v) { gAlive.fetch_add(1); }
    ~Thing()
    {
        gAlive.fetch_sub(1);
        if (tRealtime) gDeletedOnRealtime.fetch_add(1);
    }
    int value;
};

} // namespace

TEST_CASE("handover: one object in flight; the replaced one waits for the builder", "[core][handover]")
{
    gAlive = 0;
    {
        Handover<Thing> h;
        CHECK(h.active() == nullptr);
        CHECK(h.canOffer());
        auto a = std::make_unique<Thing>(1);
        REQUIRE(h.offer(a));
        CHECK(a == nullptr);
        CHECK(h.newest()->value == 1);
        auto b = std::make_unique<Thing>(2);
        CHECK_FALSE(h.offer(b));   // the first has not been taken
        CHECK(b != nullptr);       // given back untouched
        int finished = -1;
        CHECK(h.takeOffered([&](Thing* old) noexcept { finished = old == nullptr ? 0 : old->value; }));
        CHECK(finished == 0);   // nothing was active before
        CHECK(h.active()->value == 1);
        CHECK_FALSE(h.takeOffered());
        REQUIRE(h.offer(b));
        CHECK(h.takeOffered([&](Thing* old) noexcept {
            finished = old->value;      // still alive and still the real-time side's: it may end its notes
            CHECK(gAlive == 2);
        }));
        CHECK(finished == 1);
        CHECK(h.active()->value == 2);
        CHECK(gAlive == 2);
        auto c = std::make_unique<Thing>(3);
        CHECK_FALSE(h.offer(c));   // the replaced one is not collected yet
        h.collect();
        CHECK(gAlive == 2);        // 2 active, 3 still ours
        REQUIRE(h.offer(c));
        h.replace(std::make_unique<Thing>(4));   // real-time side stopped: 2 and the pending 3 go
        CHECK(h.active()->value == 4);
        CHECK(h.newest()->value == 4);
        CHECK(gAlive == 1);
    }
    CHECK(gAlive == 0);
}

TEST_CASE("handover: under a racing builder and real-time thread nothing leaks and nothing is freed on the real-time side", "[core][handover][threads]")
{
    gAlive = 0;
    gDeletedOnRealtime = 0;
    {
        Handover<Thing> h;
        std::atomic<bool> done {false};
        std::atomic<long> seen {0};
        std::atomic<bool> outOfOrder {false};   // Catch2 assertions stay on the test's thread
        std::thread realtime([&] {
            tRealtime = true;
            long last = -1;
            while (!done.load()) {
                h.takeOffered();
                if (Thing* t = h.active(); t != nullptr && t->value != last) {
                    if (t->value <= last) outOfOrder = true;   // must come in the order offered
                    last = t->value;
                    seen.fetch_add(1);
                }
            }
        });
        int offered = 0;
        // A hang guard, not a timer: the loop ends when all are offered, or after a minute.
        const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        auto next = std::make_unique<Thing>(0);
        while (offered < 2000 && std::chrono::steady_clock::now() < giveUp) {
            h.collect();
            if (h.offer(next)) next = std::make_unique<Thing>(++offered);
            else std::this_thread::yield();   // the real-time thread has not taken the last one yet
        }
        next.reset();
        while (!h.canOffer()) h.collect();   // the last one taken
        done = true;
        realtime.join();
        CHECK(offered == 2000);
        CHECK(seen.load() >= 1);
        CHECK_FALSE(outOfOrder.load());
        CHECK(gAlive == 1);   // only the active one
    }
    CHECK(gAlive == 0);
    CHECK(gDeletedOnRealtime == 0);
}
