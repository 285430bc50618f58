// What of the procedures runs off the front end's thread is real-time (STYLE.md convention 5):
// DeviceCalibration::offer on the link thread, the players' onPacket in the control step while a
// touch test or a training plays, and the calibration rehearsal's motion on the simulator's thread.
// None of it allocates, locks or throws (RealtimeGuard counts this thread's calls).
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Common/ScratchDir.h"
#include "Procedures/AdaptiveTraining.h"
#include "Procedures/DeviceCalibration.h"
#include "Procedures/TouchTest.h"
#include <catch2/catch.hpp>

using namespace armadillo;
using namespace armadillo::tactile;
using armadillo::test::RealtimeGuard;

TEST_CASE("procedures: the link thread's offer, the control step's players and the rehearsal allocate, lock and throw nothing",
          "[procedures][realtime]")
{
    ARMADILLO_REQUIRE_GUARD_SEES_ALLOCATION();
    procedures::DeviceCalibration calibration;
    calibration.begin(link::defaultCalibration());
    procedures::CalibrationRehearsal rehearsal;
    rehearsal.setStep(procedures::DeviceCalibration::Step::MagVertical);
    {
        RealtimeGuard guard;
        double sum = 0.0;
        for (int i = 0; i < 3000; ++i) {   // past the queue's capacity: dropped, never blocked
            calibration.offer(0.005 * i, link::SensorCounts {});
            sum += rehearsal.at(0.005 * i).q.w();
        }
        CHECK(guard.allocations() == 0);
        CHECK(guard.locks() == 0);
        CHECK(guard.throws() == 0);
        CHECK(sum == sum);
    }
    CHECK(calibration.packetsDropped() == 3000 - procedures::DeviceCalibration::kQueueCapacity);

    procedures::TouchTest touch;
    touch.begin(1);
    access::TactilePlayer player(TactileConfig {}, 0.0);
    procedures::AdaptiveTraining training(player);
    procedures::AdaptiveTraining::Options o;
    o.profilePath = (test::scratchDir("procedures-realtime") / "reader.json").string();
    o.trials = 2;
    training.start(o);   // the first trial's cue, cells and "your turn" queued
    RealtimeGuard guard;
    for (int i = 0; i < 2000; ++i) {
        (void) touch.player().onPacket(0.005 * i);
        (void) player.onPacket(0.005 * i);
    }
    CHECK(guard.allocations() == 0);
    CHECK(guard.deallocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(touch.player().completed() >= 1);   // the stimulus was played in there
    CHECK(player.completed() >= 1);
}
