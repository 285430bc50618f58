#pragma once
// The live session as the web page sees it (web::InstrumentView, Web/WebInstrument.h): its state
// read from the session's lock-free snapshots and counters, stage commands handed to its one
// switch (live::Stage::apply), scene parameters clamped to their range (live::sceneParamValue,
// the rule the mapping uses) and stored into the scene's atomics (Scene::setParameter). Nothing
// here waits for the control step or touches the audio thread. Any thread (the web server's).
#include "Live/Session/ProcedurePages.h"
#include "Procedures/DeviceCalibration.h"
#include "Procedures/TouchTest.h"
#include "Web/WebInstrument.h"
#include <map>
#include <mutex>
#include <string>

namespace armadillo::live {

class LiveSession;

class SessionWebView final : public web::InstrumentView {
public:
    explicit SessionWebView(live::LiveSession& session);
    ~SessionWebView() override;   // the motors back to the scene

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
    live::LiveSession& session_;
    std::string source_;                       // the source in words, fixed at construction
    std::mutex mutex_;                         // values_
    std::map<std::string, double> values_;     // parameter id → value as configured or last set here
    std::mutex calibrationMutex_;              // everything below
    procedures::DeviceCalibration calibration_;
    CalibrationPage calibrationPage_;          // the page's rules (ProcedurePages.h)
    CalibrationPage::Hooks calibrationHooks_;
    void pumpCalibration();                    // raw packets into the procedure (calibrationMutex_ held)
    std::mutex touchMutex_;                    // everything below
    procedures::TouchTest touch_;              // its player has the motors while it runs
    TouchTestPage touchPage_;
    TouchTestPage::Hooks touchHooks_;
};

} // namespace armadillo::live
