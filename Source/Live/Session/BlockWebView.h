#pragma once
// The block instrument (the app, the plugin) as the web page sees it (web::InstrumentView,
// Web/WebInstrument.h; issue 47), the block clock's counterpart of SessionWebView:
//  - the arm's pose and the time from the published frame (BlockControl::latestFrame, a seqlock),
//    the stage's panic from the stage (atomics), the walk from the navigation rig — read on the
//    web server's threads, lock-free;
//  - what only the message thread may read (the source in words, its connection, rate and
//    counters, the sender's dialect, the cues, the messages) from a snapshot the front end's
//    timer refreshes (refresh(), a few times a second), under a mutex no other thread waits on
//    for long;
//  - stage commands to the instrument's one switch (live::Stage::apply);
//  - scene parameters through the host (the plugin's parameters are the host's: the page sets
//    them as an automation gesture would, on the message thread), so host automation, the
//    editor and the page never disagree.
// The sensitivity test runs on the message thread: the page's commands wait in a queue that
// refresh() takes, and the host begins and ends it (the app: its Reader window's own functions,
// so the measured profile becomes the reader's setting). The guided device calibration runs the
// same way: the page's commands go to the block rig's calibration (BlockRig: the one the
// Calibration window runs) on the message thread; a finished one is applied to the device at once
// (not saved: the page offers it to download, the window saves it).
#include "Live/Session/ProcedurePages.h"
#include "Web/WebInstrument.h"
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace armadillo::live {

class BlockInstrument;

class BlockWebView final : public web::InstrumentView {
public:
    /// The scene's parameters as the host holds them (any thread).
    struct Host {
        std::function<std::vector<web::ParameterInfo>()> parameters;
        /// Sets parameter `id` of the playing scene to `value` clamped to its range; false when the
        /// scene has no such parameter. `set` is the value it gets.
        std::function<bool(const std::string& id, double value, double& set)> setParameter;
        /// Message thread: the sensitivity test begun (the motors the test's), ended (`keep`: the
        /// measured profile becomes the reader's). Empty: the page offers no test.
        std::function<void(std::uint64_t seed)> beginTouchTest;
        std::function<void(bool keep)> endTouchTest;
        /// Any thread: the scenes the page may choose (empty with `why`), and a choice made ("" or
        /// why not; the plugin: its `scene` parameter, set on the message thread). Empty: none.
        std::function<std::vector<std::string>(std::string& why)> sceneChoices;
        std::function<std::string(const std::string& name)> chooseScene;
    };
    BlockWebView(BlockInstrument& instrument, Host host);

    /// Message thread: the part of the status only it may read. `scene`: the scene that plays.
    void refresh(const std::string& scene);

    web::InstrumentStatus status() override;
    std::vector<web::ParameterInfo> parameters() override;
    void stage(const core::StageCommand& command) override;
    bool setParameter(const std::string& id, double value, double& set) override;
    void calibration(web::ProcedureCommand command) override;
    std::string calibrationFile() override;
    std::vector<std::string> sceneChoices(std::string& why) override;
    std::string chooseScene(const std::string& name) override;
    void touchTest(web::TouchCommand command) override;
    std::string touchProfileFile() override;


private:
    BlockInstrument& instrument_;
    Host host_;
    std::mutex mutex_;                 // snapshot_
    web::InstrumentStatus snapshot_;   // message thread → web threads
    std::vector<web::TouchCommand> pendingTouch_;   // web threads → message thread (under mutex_)
    std::vector<web::ProcedureCommand> pendingCalibration_;   // likewise
    std::string calibrationFile_;      // the finished calibration as a file (under mutex_)
    std::string touchProfile_;         // the measured profile as a file (under mutex_)
    // Message thread only: the page's rules (ProcedurePages.h) and where they act here.
    TouchTestPage touchPage_;
    TouchTestPage::Hooks touchHooks_;
    web::TouchTestStatus touch_;       // what the page shows of the test, as of the last refresh
    CalibrationPage calibrationPage_;
    CalibrationPage::Hooks calibrationHooks_;
    void runTouchCommands();
    web::ProcedureStatus runCalibrationCommands();
};

} // namespace armadillo::live
