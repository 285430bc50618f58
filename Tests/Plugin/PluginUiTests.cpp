// The app's editor as a keyboard and screen-reader user meets it (issue 24), on a real window
// (run under Xvfb: ctest uses xvfb-run when installed): every control reachable with Tab in the
// layout's order, each with an accessible title and description (JUCE's accessibility handlers);
// arrows never change a setting that does not have the focus; the braille training panel owns the
// keyboard while it trains (typo refused and corrected, skip, repeat, Escape, stop); the welcome;
// the status line; the error banner that goes when the error is fixed; no overlapping panels from
// the minimum size up, 200 % scale included; Connect switches the source.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#define ARMADILLO_REALTIME_GUARD_IMPLEMENTATION
#include "Common/RealtimeGuard.h"
#include "Plugin/PluginEditor.h"
#include "Plugin/PluginProcessor.h"
#include "Braille/BrailleScene.h"
#include "Access/ReaderProfile.h"
#include "Common/FakeBrlApi.h"
#include "Plugin/ReaderPanel.h"
#include <cstdlib>
#include <functional>
#include <dlfcn.h>
#include <memory>

namespace juce {
bool dispatchNextMessageOnSystemQueue(bool returnIfNoPendingMessages);   // juce_linux_Messaging.cpp
}

using namespace armadillo;
using namespace armadillo::plugin;

namespace {

/// Runs the message loop until `done` holds or `timeoutMs` passes; returns done().
template <typename Pred>
bool pumpUntil(Pred done, double timeoutMs = 5000.0)
{
    const double end = juce::Time::getMillisecondCounterHiRes() + timeoutMs;
    while (! done()) {
        if (juce::Time::getMillisecondCounterHiRes() > end) return false;
        if (! juce::dispatchNextMessageOnSystemQueue(true)) juce::Thread::sleep(1);
    }
    return true;
}

void pumpFor(double ms)
{
    pumpUntil([] { return false; }, ms);
}

struct App {
    std::unique_ptr<ArmadilloProcessor> processor;
    std::unique_ptr<ArmadilloEditor> editor;
    App()
    {
        processor = std::make_unique<ArmadilloProcessor>();
        editor.reset(static_cast<ArmadilloEditor*>(processor->createEditor()));
        editor->setSize(1000, 700);
        editor->addToDesktop(0);
        editor->setVisible(true);
        pumpUntil([&] { return editor->isShowing(); });
    }
    ~App()
    {
        editor.reset();
        processor.reset();
    }
    void setParam(const char* id, float value)
    {
        auto* p = processor->parameters().getParameter(id);
        REQUIRE(p != nullptr);
        p->setValueNotifyingHost(p->convertTo0to1(value));
    }
    float param(const char* id) const
    {
        auto* p = processor->parameters().getParameter(id);
        return p->convertFrom0to1(p->getValue());
    }
    int sceneIndexOf(const std::string& name) const
    {
        const auto& scenes = processor->sceneTable().scenes;
        for (std::size_t i = 0; i < scenes.size(); ++i)
            if (scenes[i].scene == name) return static_cast<int>(i);
        return -1;
    }
    bool press(juce::Component& target, const juce::KeyPress& key)
    {
        // As the window's peer delivers a key: to the focused component, then up its parents.
        for (auto* c = &target; c != nullptr; c = c->getParentComponent())
            if (c->keyPressed(key)) return true;
        return false;
    }
};

juce::String nameOf(juce::Component* c)
{
    return c->getTitle().isNotEmpty() ? c->getTitle() : c->getName();
}

/// One stop of the Tab walk, read while the component has the focus (some exist only then: a
/// label's text editor while it edits).
struct Stop {
    juce::Component* component = nullptr;   // compare only: it may be gone after the walk
    juce::String name, type, accessibleTitle;
    bool hasHandler = false, described = false;
};

std::vector<Stop> tabWalk(juce::Component& start)
{
    std::vector<Stop> stops;
    start.grabKeyboardFocus();
    auto* first = juce::Component::getCurrentlyFocusedComponent();
    for (auto* now = first; now != nullptr;) {
        Stop s;
        s.component = now;
        s.name = nameOf(now);
        s.type = typeid(*now).name();
        if (auto* handler = now->getAccessibilityHandler()) {
            s.hasHandler = true;
            s.accessibleTitle = handler->getTitle();
        }
        s.described = now->getDescription().isNotEmpty() || now->getHelpText().isNotEmpty();
        stops.push_back(s);
        if (stops.size() > 400) break;
        now->moveKeyboardFocusToSibling(true);
        now = juce::Component::getCurrentlyFocusedComponent();
        if (now == first) break;
    }
    return stops;
}

std::vector<juce::Component*> tabOrder(juce::Component& start)
{
    std::vector<juce::Component*> order;
    for (const auto& s : tabWalk(start)) order.push_back(s.component);
    return order;
}

} // namespace

TEST_CASE("editor: Tab reaches every control in layout order; each has an accessible title and description", "[plugin][ui]")
{
    App app;
    auto& ed = *app.editor;
    const auto stops = tabWalk(ed);
    REQUIRE(stops.size() >= 30);
    std::vector<juce::String> names;
    std::vector<juce::Component*> order;
    for (const auto& s : stops) {
        names.push_back(s.name);
        order.push_back(s.component);
        INFO("focusable component " << s.name << " (" << s.type << ")");
        REQUIRE(s.hasHandler);
        CHECK(s.accessibleTitle.isNotEmpty());
        // Every control says what it is for (text fields and labels read their text as well).
        CHECK(s.described);
    }
    // The top bar comes first, left to right; the status line last.
    REQUIRE(names.size() > 10);
    CHECK(names[0] == "Source");
    CHECK(names[1] == "Scene");
    CHECK(names[2] == "Preset");
    CHECK(names[3] == "Simulator wandering");
    CHECK(names[4] == "Reader settings");
    CHECK(names[5] == "Mapping editor");
    CHECK(names[6] == "Stage");
    CHECK(names[7] == "Setup");
    CHECK(names[8] == "Help");
    CHECK(names[9] == "About ARMadillo");
    CHECK(names.back() == "Status");
    // The panels in between: arm view before the motors before the device panel's port list.
    const auto at = [&](const juce::String& n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
    CHECK(at("Arm view") < at("Motor display"));
    CHECK(at("Motor display") < at("Serial port"));
    CHECK(at("Serial port") < at("OSC input"));
    CHECK(at("OSC input") < at("Left arm OSC input"));   // issue 28: the left arm's sender, then its port
    CHECK(at("Left arm OSC input") + 1 == at("Left arm OSC input port"));
    // Every showing control that wants the keyboard is in the order (nothing unreachable).
    std::function<void(juce::Component&)> visit = [&](juce::Component& c) {
        for (auto* child : c.getChildren()) {
            if (! child->isShowing() || ! child->isEnabled()) continue;
            if (child->getWantsKeyboardFocus() && &c != &app.editor->welcome()) {
                INFO("unreachable: " << nameOf(child));
                CHECK(std::find(order.begin(), order.end(), child) != order.end());
            }
            if (child != &app.editor->training()) visit(*child);
        }
    };
    visit(ed);
}

TEST_CASE("editor: arrows act on the focused control only; a choice box opens its list instead of stepping", "[plugin][ui]")
{
    App app;
    const float scene = app.param(ParamIds::scene);
    const float source = app.param(ParamIds::source);
    auto order = tabOrder(*app.editor);
    REQUIRE(order.size() > 2);
    auto* sceneBox = order[1];
    sceneBox->grabKeyboardFocus();
    for (auto key : {juce::KeyPress::downKey, juce::KeyPress::upKey, juce::KeyPress::rightKey})
        app.press(*sceneBox, juce::KeyPress(key));
    juce::PopupMenu::dismissAllActiveMenus();
    pumpFor(50);
    CHECK(app.param(ParamIds::scene) == scene);
    // With the focus on a button, arrows reach nothing that changes the scene or source.
    order[5]->grabKeyboardFocus();   // Help
    for (auto key : {juce::KeyPress::downKey, juce::KeyPress::upKey, juce::KeyPress::leftKey, juce::KeyPress::rightKey})
        app.press(*order[5], juce::KeyPress(key));
    pumpFor(50);
    CHECK(app.param(ParamIds::scene) == scene);
    CHECK(app.param(ParamIds::source) == source);
}

TEST_CASE("editor: the mouse wheel changes a slider only when it has the focus or with Ctrl", "[plugin][ui]")
{
    App app;
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("theremin")));
    std::vector<juce::Slider*> sliders;
    REQUIRE(pumpUntil([&] {
        sliders.clear();
        std::function<void(juce::Component&)> find = [&](juce::Component& c) {
            for (auto* child : c.getChildren()) {
                if (auto* s = dynamic_cast<juce::Slider*>(child); s != nullptr && s->isShowing()) sliders.push_back(s);
                find(*child);
            }
        };
        find(*app.editor);
        return ! sliders.empty();
    }));
    auto* slider = sliders.front();
    const double before = slider->getValue();
    auto source = juce::Desktop::getInstance().getMainMouseSource();
    const auto centre = slider->getLocalBounds().getCentre().toFloat();
    juce::MouseWheelDetails wheel {};
    wheel.deltaY = 0.5f;
    // Each event its own time stamp (the slider ignores a second wheel event of the same time).
    juce::int64 stamp = juce::Time::currentTimeMillis();
    const auto event = [&](juce::ModifierKeys mods) {
        stamp += 100;
        return juce::MouseEvent(source, centre, mods, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, slider, slider, juce::Time(stamp), centre,
                                juce::Time(stamp), 0, false);
    };
    app.editor->grabKeyboardFocus();
    juce::Component::unfocusAllComponents();
    slider->mouseWheelMove(event({}), wheel);
    CHECK(slider->getValue() == before);
    slider->mouseWheelMove(event(juce::ModifierKeys::ctrlModifier), wheel);
    CHECK(slider->getValue() != before);
    const double afterCtrl = slider->getValue();
    slider->grabKeyboardFocus();
    REQUIRE(slider->hasKeyboardFocus(true));
    slider->mouseWheelMove(event({}), wheel);
    CHECK(slider->getValue() != afterCtrl);
}

TEST_CASE("editor: the braille training panel owns the keyboard; typos are corrected before sending", "[plugin][ui][training]")
{
    App app;
    auto& panel = app.editor->training();
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("braille")));
    app.setParam("braille.mode", static_cast<float>(braille::BrailleMode::Training));
    REQUIRE(pumpUntil([&] { return panel.isShowing() && panel.promptText().isNotEmpty(); }));
    // Focus goes to the answer field (not left on a Mode box).
    REQUIRE(pumpUntil([&] { return panel.answerField().hasKeyboardFocus(false); }, 2000.0));

    std::string expected0;
    REQUIRE(app.processor->withBrailleTraining([&](braille::BrailleSceneControls& s, std::uint64_t) { expected0 = s.trainingExpected(0); }));
    // The first stage asks left, right or both: a typo is refused and stays in the field.
    REQUIRE((expected0 == "left" || expected0 == "right" || expected0 == "both"));
    auto& field = panel.answerField();
    field.setText("lefy");
    panel.submit();
    CHECK(panel.resultText().startsWith("Not sent: 'lefy' is not left, right or both"));
    CHECK(field.getText() == "lefy");
    CHECK(panel.scoreText() == "0 of 0 correct");
    // Corrected, then Return: the right answer is scored "correct".
    field.setText(juce::String(expected0));
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::returnKey)));
    REQUIRE(pumpUntil([&] { return panel.resultText() == "correct"; }));
    CHECK(panel.scoreText() == "1 of 1 correct");
    CHECK(panel.tallyText().contains(juce::String(expected0) + " 1/1"));

    // A wrong answer says what it was, unmistakably (never "right" for "correct").
    std::string expected1;
    app.processor->withBrailleTraining([&](braille::BrailleSceneControls& s, std::uint64_t) { expected1 = s.trainingExpected(1); });
    const std::string wrong = expected1 == "left" ? "right" : "left";
    field.setText(juce::String(wrong));
    panel.submit();
    REQUIRE(pumpUntil([&] { return panel.resultText().startsWith("wrong"); }));
    CHECK(panel.resultText() == "wrong, it was '" + juce::String(expected1) + "', you answered '" + juce::String(wrong) + "'");

    // F6 skips (counted wrong), F5 repeats the prompt; arrows do nothing outside the panel.
    const float scene = app.param(ParamIds::scene);
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::F6Key)));
    REQUIRE(pumpUntil([&] { return panel.resultText().startsWith("skipped (counts as wrong)"); }));
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::F5Key)));
    CHECK(panel.resultText().startsWith("Prompt again: Trial 4 of"));
    for (auto key : {juce::KeyPress::upKey, juce::KeyPress::downKey}) app.press(field, juce::KeyPress(key));
    CHECK(app.param(ParamIds::scene) == scene);
    CHECK(app.param("braille.mode") == static_cast<float>(braille::BrailleMode::Training));

    // Tab stays inside the panel while it trains.
    for (int i = 0; i < 20; ++i) {
        auto* now = juce::Component::getCurrentlyFocusedComponent();
        REQUIRE(now != nullptr);
        now->moveKeyboardFocusToSibling(true);
        CHECK(panel.isParentOf(juce::Component::getCurrentlyFocusedComponent()));
    }
    // Escape leaves it (focus on the Scene box); Tab brings the reader back to the answer field.
    panel.answerField().grabKeyboardFocus();
    CHECK(app.press(panel.answerField(), juce::KeyPress(juce::KeyPress::escapeKey)));
    // (a text field reports Escape through a message: the focus moves when it is handled)
    REQUIRE(pumpUntil([&] { return ! panel.answerField().hasKeyboardFocus(false); }, 2000.0));
    auto* outside = juce::Component::getCurrentlyFocusedComponent();
    REQUIRE(outside != nullptr);
    CHECK_FALSE(panel.isParentOf(outside));
    CHECK(nameOf(outside) == "Scene");
    panel.grabKeyboardFocus();
    CHECK(panel.answerField().hasKeyboardFocus(false));

    // F8 stops the training: back to active reading, the panel goes.
    CHECK(app.press(panel.answerField(), juce::KeyPress(juce::KeyPress::F8Key)));
    CHECK(app.param("braille.mode") == static_cast<float>(braille::BrailleMode::Active));
    REQUIRE(pumpUntil([&] { return ! panel.isVisible(); }));
}

TEST_CASE("editor: the welcome says what plays and how to hear it; Escape closes, Help reopens", "[plugin][ui][welcome]")
{
    App app;
    auto& welcome = app.editor->welcome();
    app.editor->showHelp();
    REQUIRE(welcome.isShowing());
    CHECK(welcome.text().contains("Playing now: the simulated arm"));
    CHECK(welcome.text().contains("Hearing it: the host's audio output"));   // not the standalone app here
    CHECK(welcome.text().contains("A real arm: choose its port in the device panel and press Connect"));
    auto* focused = juce::Component::getCurrentlyFocusedComponent();
    REQUIRE(focused != nullptr);
    CHECK(welcome.isParentOf(focused));
    // Tab stays in the welcome while it is open.
    for (int i = 0; i < 12; ++i) {
        juce::Component::getCurrentlyFocusedComponent()->moveKeyboardFocusToSibling(true);
        CHECK(welcome.isParentOf(juce::Component::getCurrentlyFocusedComponent()));
    }
    CHECK(app.press(*juce::Component::getCurrentlyFocusedComponent(), juce::KeyPress(juce::KeyPress::escapeKey)));
    CHECK_FALSE(welcome.isVisible());
    CHECK(app.press(*app.editor, juce::KeyPress(juce::KeyPress::F1Key)));
    CHECK(welcome.isVisible());
}

TEST_CASE("editor: the status line names the source; Connect switches to the device; silence shows within a second", "[plugin][ui][status]")
{
    App app;
    REQUIRE(pumpUntil([&] { return app.editor->statusLine().getText().contains("steps/s"); }));
    CHECK(app.editor->statusLine().getText().startsWith("Source: simulated arm"));
    // Connect on the simulated forearm: the source becomes the device and its packets are counted.
    app.processor->settings().setProperty(SettingIds::serialPort, live::DeviceConnection::kSimulatedPort, nullptr);
    app.processor->connectDevice(true);
    CHECK(app.processor->source() == SourceKind::Device);
    REQUIRE(pumpUntil([&] { return app.editor->statusLine().getText().contains("packets/s"); }));
    // Disconnected: never shown as alive.
    app.processor->connectDevice(false);
    REQUIRE(pumpUntil([&] { return app.editor->statusLine().getText().contains("device, not connected"); }, 1000.0));
    // OSC with its input on but nobody sending: silent within a second.
    app.processor->settings().setProperty(SettingIds::oscInPort, 49123, nullptr);
    app.processor->settings().setProperty(SettingIds::oscInEnabled, true, nullptr);
    app.setParam(ParamIds::source, static_cast<float>(SourceKind::Osc));
    const double start = juce::Time::getMillisecondCounterHiRes();
    REQUIRE(pumpUntil([&] { return app.editor->statusLine().getText().contains("OSC port 49123 (silent"); }, 1500.0));
    CHECK(juce::Time::getMillisecondCounterHiRes() - start <= 1200.0);   // the timer's 0.1 s and a loaded machine's slack
}

TEST_CASE("editor: a score error banner goes once the score is fixed", "[plugin][ui][banner]")
{
    App app;
    app.processor->settings().setProperty(SettingIds::score, "/nonexistent/folder/missing.score", nullptr);
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("score")));
    REQUIRE(pumpUntil([&] { return app.processor->statusMessage().contains("cannot start"); }));
    REQUIRE(pumpUntil([&] {
        for (auto* c : app.editor->getChildren())
            if (auto* l = dynamic_cast<juce::Label*>(c); l != nullptr && l->isVisible() && l->getText().contains("cannot start")) return true;
        return false;
    }));
    app.processor->settings().setProperty(SettingIds::score, "rite-of-spring", nullptr);
    REQUIRE(pumpUntil([&] { return app.processor->statusMessage().isEmpty(); }));
    pumpFor(300);
    for (auto* c : app.editor->getChildren())
        if (auto* l = dynamic_cast<juce::Label*>(c); l != nullptr && l->isVisible()) CHECK_FALSE(l->getText().contains("cannot start"));
}

TEST_CASE("a loaded state whose scene cannot start shows the banner", "[plugin][ui][banner]")
{
    juce::MemoryBlock saved;
    {
        App app;
        app.processor->settings().setProperty(SettingIds::score, "/nonexistent/folder/missing.score", nullptr);
        app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("score")));
        REQUIRE(pumpUntil([&] { return app.processor->statusMessage().contains("cannot start"); }));
        app.processor->getStateInformation(saved);
    }
    // A session reopened: the state's scene is built as the state comes, and its failure is what
    // the banner says (not the state's own, empty, message written after it).
    App app;
    app.processor->setStateInformation(saved.getData(), static_cast<int>(saved.getSize()));
    CHECK(pumpUntil([&] { return app.processor->statusMessage().contains("cannot start"); }, 2000.0));
}

TEST_CASE("editor: no panels overlap from the minimum size up, at 100 % and 200 % scale", "[plugin][ui][layout]")
{
    App app;
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("braille")));
    app.setParam("braille.mode", static_cast<float>(braille::BrailleMode::Training));
    REQUIRE(pumpUntil([&] { return app.editor->training().isShowing(); }));
    for (const float scale : {1.0f, 2.0f}) {
        juce::Desktop::getInstance().setGlobalScaleFactor(scale);
        for (const auto& size : {juce::Point<int>(720, 520), juce::Point<int>(1366, 768), juce::Point<int>(1920, 1080)}) {
            app.editor->setSize(size.x, size.y);
            pumpFor(30);
            INFO("size " << size.x << "x" << size.y << " at scale " << scale);
            std::vector<juce::Component*> shown;
            // (the window's resize corner sits over the corner of the editor, by design)
            for (auto* c : app.editor->getChildren())
                if (c->isVisible() && c != &app.editor->welcome() && c != &app.editor->performance() && dynamic_cast<juce::Label*>(c) == nullptr
                    && dynamic_cast<juce::ResizableCornerComponent*>(c) == nullptr)
                    shown.push_back(c);
            for (auto* c : app.editor->getChildren())
                if (c->isVisible() && (c == &app.editor->statusLine())) shown.push_back(c);
            for (std::size_t i = 0; i < shown.size(); ++i) {
                INFO(nameOf(shown[i]) << " " << shown[i]->getBounds().toString().toStdString());
                CHECK(app.editor->getLocalBounds().contains(shown[i]->getBounds()));
                CHECK(shown[i]->getWidth() > 0);
                CHECK(shown[i]->getHeight() > 0);
                for (std::size_t j = i + 1; j < shown.size(); ++j) {
                    INFO("against " << nameOf(shown[j]) << " " << shown[j]->getBounds().toString().toStdString());
                    CHECK_FALSE(shown[i]->getBounds().intersects(shown[j]->getBounds()));
                }
            }
            // The welcome fits its page whole: nothing (its Close button least of all) cut off.
            app.editor->showHelp();
            pumpFor(20);
            std::vector<juce::Component*> page;
            for (auto* c : app.editor->welcome().getChildren())
                if (c->isVisible()) page.push_back(c);
            for (std::size_t i = 0; i < page.size(); ++i) {
                INFO("welcome: " << nameOf(page[i]) << " " << page[i]->getBounds().toString().toStdString() << " in "
                                 << app.editor->welcome().getLocalBounds().toString().toStdString());
                CHECK(app.editor->welcome().getLocalBounds().contains(page[i]->getBounds()));
                CHECK(page[i]->getHeight() >= 12);
                for (std::size_t j = i + 1; j < page.size(); ++j) {
                    INFO("against " << nameOf(page[j]) << " " << page[j]->getBounds().toString().toStdString());
                    CHECK_FALSE(page[i]->getBounds().intersects(page[j]->getBounds()));
                }
            }
            app.editor->welcome().close();
            // The performance view (issue 28): its lines, PANIC and buttons fit and do not overlap.
            app.editor->showPerformance();
            pumpFor(20);
            std::vector<juce::Component*> perf;
            for (auto* c : app.editor->performance().getChildren())
                if (c->isVisible()) perf.push_back(c);
            REQUIRE(perf.size() == 9);
            for (std::size_t i = 0; i < perf.size(); ++i) {
                INFO("performance: " << nameOf(perf[i]) << " " << perf[i]->getBounds().toString().toStdString());
                CHECK(app.editor->performance().getLocalBounds().contains(perf[i]->getBounds()));
                CHECK(perf[i]->getHeight() >= 20);
                for (std::size_t j = i + 1; j < perf.size(); ++j) {
                    INFO("against " << nameOf(perf[j]) << " " << perf[j]->getBounds().toString().toStdString());
                    CHECK_FALSE(perf[i]->getBounds().intersects(perf[j]->getBounds()));
                }
            }
            app.editor->performance().close();
            // Inside the training panel too (the device panel scrolls rather than squeezes).
            for (juce::Component* panel : {static_cast<juce::Component*>(&app.editor->training())}) {
                std::vector<juce::Component*> inner;
                for (auto* c : panel->getChildren())
                    if (c->isVisible()) inner.push_back(c);
                for (std::size_t i = 0; i < inner.size(); ++i)
                    for (std::size_t j = i + 1; j < inner.size(); ++j) {
                        INFO(nameOf(inner[i]) << " vs " << nameOf(inner[j]));
                        CHECK_FALSE(inner[i]->getBounds().intersects(inner[j]->getBounds()));
                    }
            }
        }
    }
    juce::Desktop::getInstance().setGlobalScaleFactor(1.0f);
}

TEST_CASE("editor: the performance view steps the set list by key and Escape panics (F12 in the editor); Tab reaches its controls", "[plugin][ui][stage]")
{
    App app;
    const char* cues = R"({"armadillo_setlist": 1, "cues": [
        {"name": "Intro", "scene": "theremin"}, {"name": "Gestures", "scene": "sound-design"},
        {"name": "Wide", "scene": "theremin", "parameters": {"theremin.range": 24}}, {"name": "Panel", "scene": "panel"}]})";
    REQUIRE(app.processor->useSetList(cues, "show.json") == "");
    // No audio device here: the app's idle control clock runs the control step (as on a laptop
    // without a sound card), so the keys act within a few of its steps.
    auto& ed = *app.editor;
    CHECK(app.press(ed, juce::KeyPress(juce::KeyPress::F11Key)));
    auto& view = ed.performance();
    REQUIRE(pumpUntil([&] { return view.isShowing() && view.hasKeyboardFocus(true); }));
    view.refresh();
    CHECK(view.cueLine().contains("Cue 1/4: Intro"));
    CHECK(view.nextLine().contains("Next 2: Gestures"));
    CHECK(view.armLine().contains("Right arm: simulator"));
    CHECK(view.armLine().contains("Left: none"));
    // Issue 28: with an OSC sender as the left arm the line names its port, silent until it sends.
    {
        juce::DatagramSocket probe;
        REQUIRE(probe.bindToPort(0, "127.0.0.1"));
        const int port = probe.getBoundPort();
        probe.shutdown();
        app.processor->settings().setProperty(SettingIds::leftArmOscPort, port, nullptr);
        app.processor->settings().setProperty(SettingIds::leftArmOsc, true, nullptr);
        REQUIRE(app.processor->leftArmOn());
        view.refresh();
        CHECK(view.armLine().contains("Left arm: OSC port " + juce::String(port) + " SILENT"));
        app.processor->settings().setProperty(SettingIds::leftArmOsc, false, nullptr);
        view.refresh();
        CHECK(view.armLine().contains("Left: none"));
    }
    CHECK(view.stateLine() == "Playing");
    auto* focused = juce::Component::getCurrentlyFocusedComponent();
    REQUIRE(focused != nullptr);
    CHECK(app.press(*focused, juce::KeyPress('n')));
    REQUIRE(pumpUntil([&] { return app.processor->stageInfo().cue == 1; }));
    CHECK(app.press(*focused, juce::KeyPress(juce::KeyPress::spaceKey)));
    REQUIRE(pumpUntil([&] { return app.processor->stageInfo().cue == 2; }));
    CHECK(app.press(*focused, juce::KeyPress('b')));
    REQUIRE(pumpUntil([&] { return app.processor->stageInfo().cue == 1; }));
    REQUIRE(pumpUntil([&] { view.refresh(); return view.cueLine().contains("Cue 2/4: Gestures"); }));
    CHECK(pumpUntil([&] { return app.processor->statusMessage().contains("Cue 2 of 4"); }));
    // The panic key: all motors off on the next idle steps, PANIC shown, reported in the status line.
    CHECK(app.press(*focused, juce::KeyPress(juce::KeyPress::escapeKey)));
    CHECK(app.processor->panicked());
    REQUIRE(pumpUntil([&] { return app.processor->statusMessage().startsWith("PANIC"); }));
    pumpFor(100);
    const auto f = app.processor->latestFrame();
    for (int i = 0; i < f.motorCount; ++i) CHECK(f.motors[static_cast<std::size_t>(i)] == 0);
    view.refresh();
    CHECK(view.stateLine().startsWith("PANIC"));
    CHECK(app.press(*focused, juce::KeyPress('r')));
    CHECK_FALSE(app.processor->panicked());
    REQUIRE(pumpUntil([&] { return app.processor->statusMessage() == "Resumed."; }));
    CHECK(app.processor->stageInfo().cue == 1);   // back to the current cue
    // The big button panics too.
    view.panicButton().triggerClick();
    REQUIRE(pumpUntil([&] { return app.processor->panicked(); }));
    app.processor->resume();
    // Tab: the view's lines and buttons, each named and described.
    std::vector<juce::String> names;
    for (const auto& s : tabWalk(view.panicButton())) {
        INFO(s.name << " (" << s.type << ")");
        CHECK(s.hasHandler);
        CHECK(s.accessibleTitle.isNotEmpty());
        names.push_back(s.name);
    }
    for (const char* n : {"Panic", "Resume", "Previous cue", "Next cue", "Close the performance view", "Current cue", "Coming next", "Arms", "Panic state"})
        CHECK(std::find(names.begin(), names.end(), juce::String(n)) != names.end());
    // c closes; in the editor F12 panics (the panic key), whichever control has the focus.
    CHECK(app.press(view, juce::KeyPress('c')));
    CHECK_FALSE(view.isVisible());
    CHECK(app.press(ed, juce::KeyPress(juce::KeyPress::F12Key)));
    CHECK(app.processor->panicked());
    app.processor->resume();
}

TEST_CASE("processor: the welcome's test tone is heard for its length, and processBlock stays real-time", "[plugin][ui][tone]")
{
    using armadillo::test::RealtimeGuard;
    ARMADILLO_REQUIRE_GUARD();
    {
        RealtimeGuard probe;   // the guard sees an allocation before its zero is trusted
        auto p = std::make_unique<double>(1.0);
        CHECK(probe.allocations() >= 1);
    }
    ArmadilloProcessor processor;
    auto* scene = processor.parameters().getParameter(ParamIds::scene);
    const auto& scenes = processor.sceneTable().scenes;
    int monitor = -1;
    for (std::size_t i = 0; i < scenes.size(); ++i)
        if (scenes[i].scene == "monitor") monitor = static_cast<int>(i);
    REQUIRE(monitor >= 0);
    scene->setValueNotifyingHost(scene->convertTo0to1(static_cast<float>(monitor)));   // silent: the tone alone
    constexpr int block = 480;   // 10 ms at 48 kHz
    processor.prepareToPlay(48000.0, block);
    juce::AudioBuffer<float> buffer(2, block);
    juce::MidiBuffer midi;
    const auto run = [&] {
        buffer.clear();
        midi.clear();
        processor.processBlock(buffer, midi);
        return std::max(buffer.getMagnitude(0, 0, block), buffer.getMagnitude(1, 0, block));
    };
    for (int i = 0; i < 20; ++i) run();
    CHECK(run() < 1.0e-6f);
    const auto before = processor.audioBlocks();
    processor.takeOutputPeak();
    processor.playTestTone(0.1);   // 4800 samples: 10 blocks
    RealtimeGuard guard;
    float peak = 0.0f;
    for (int i = 0; i < 10; ++i) peak = std::max(peak, run());
    const float after = run();
    CHECK(guard.allocations() == 0);
    CHECK(guard.locks() == 0);
    CHECK(guard.throws() == 0);
    CHECK(peak == Approx(0.125f).epsilon(0.01));          // -18 dBFS, 440 Hz
    CHECK(after < 1.0e-6f);                               // it stops when its time is over
    CHECK(processor.takeOutputPeak() == Approx(0.125f).epsilon(0.01));   // the status line's peak saw it
    CHECK(processor.audioBlocks() - before == 11);
    processor.releaseResources();
}

/// JUCE installs its forgiving X error handlers only in a JUCE application (a plugin's host
/// installs its own); without a window manager Xvfb lacks atoms such as WM_STATE, and Xlib's
/// default handler would exit on the first harmless BadAtom. The test, as a host, installs one
/// that ignores them (libX11 is the one JUCE loaded at run time).
int ignoreXError(void*, void*)
{
    return 0;
}

void installXErrorHandler()
{
    if (void* x11 = dlopen("libX11.so.6", RTLD_LAZY | RTLD_GLOBAL)) {
        using Handler = int (*)(void*, void*);
        using SetHandler = Handler (*)(Handler);
        if (auto set = reinterpret_cast<SetHandler>(dlsym(x11, "XSetErrorHandler"))) set(&ignoreXError);
    }
}

int main(int argc, char* argv[])
{
    if (juce::SystemStats::getEnvironmentVariable("DISPLAY", {}).isEmpty()) {
        std::cout << "tests_plugin_ui: skipped, no X display (run it under xvfb-run; ctest does when xvfb-run is installed)\n";
        return 0;
    }
    // The welcome's "show at start" lives in ~/.config/armadillo: keep the tester's own untouched.
    const auto home = juce::File::createTempFile("armadillo-ui-home");
    home.createDirectory();
    setenv("HOME", home.getFullPathName().toRawUTF8(), 1);
    setenv("XDG_RUNTIME_DIR", home.getFullPathName().toRawUTF8(), 1);
    int result = 0;
    {
        juce::ScopedJuceInitialiser_GUI gui;
        installXErrorHandler();
        result = Catch::Session().run(argc, argv);
        juce::Desktop::getInstance().setGlobalScaleFactor(1.0f);
    }
    home.deleteRecursively();
    return result;
}

TEST_CASE("processor: MIDI learn takes the next message at the plugin's MIDI input as a mapping's destination", "[plugin][mapping][learn]")
{
    // Issue 23: "learn" a destination from the next CC another plugin's automation lane or a
    // controller sends. The message goes in through processBlock's MIDI buffer, as a host sends it.
    ArmadilloProcessor processor;
    constexpr int block = 480;
    processor.prepareToPlay(48000.0, block);
    juce::AudioBuffer<float> buffer(2, block);
    juce::MidiBuffer midi;
    const auto run = [&](const juce::MidiMessage* in) {
        buffer.clear();
        midi.clear();
        if (in != nullptr) midi.addEvent(*in, 17);
        processor.processBlock(buffer, midi);
    };
    for (int i = 0; i < 5; ++i) run(nullptr);
    {
        auto m = processor.mapping();
        REQUIRE(! m->document().mappings.empty());
        m->startDestinationLearn(0);
    }
    const auto cc = juce::MidiMessage::controllerEvent(5, 74, 90);   // channel 5, CC 74
    run(&cc);
    for (int i = 0; i < 3; ++i) run(nullptr);
    armadillo::mapping::DestinationSpec learned;
    juce::String notice;
    for (int tick = 0; tick < 20 && notice.isEmpty(); ++tick) {
        auto m = processor.mapping();
        m->timerTick();
        notice = m->takeNotice();
        learned = m->document().mappings[0].to;
    }
    INFO(notice);
    CHECK(notice.isNotEmpty());
    CHECK(learned.kind == armadillo::mapping::DestinationKind::Cc7);
    CHECK(learned.channel == 5);
    CHECK(learned.number == 74);
    CHECK(processor.mapping()->destinationLearnIndex() == -1);   // one message learns once

    // A CC 0-31 followed by its +32 partner is learned as a 14-bit pair.
    processor.mapping()->startDestinationLearn(0);
    const auto msb = juce::MidiMessage::controllerEvent(2, 7, 64), lsb = juce::MidiMessage::controllerEvent(2, 39, 0);
    buffer.clear();
    midi.clear();
    midi.addEvent(msb, 3);
    midi.addEvent(lsb, 4);
    processor.processBlock(buffer, midi);
    notice.clear();
    for (int tick = 0; tick < 20 && notice.isEmpty(); ++tick) {
        auto m = processor.mapping();
        m->timerTick();
        notice = m->takeNotice();
        learned = m->document().mappings[0].to;
    }
    INFO(notice);
    CHECK(learned.kind == armadillo::mapping::DestinationKind::Cc14);
    CHECK(learned.channel == 2);
    CHECK(learned.number == 7);
}

TEST_CASE("editor: the score list's Import a file item and its description name bHaptics .tact", "[plugin][ui][score]")
{
    App app;
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("score")));
    juce::ComboBox* box = nullptr;
    const std::function<void(juce::Component&)> find = [&](juce::Component& c) {
        if (auto* b = dynamic_cast<juce::ComboBox*>(&c); b != nullptr && b->getTitle() == "Score") box = b;
        for (auto* child : c.getChildren()) find(*child);
    };
    REQUIRE(pumpUntil([&] {
        box = nullptr;
        find(*app.editor);
        return box != nullptr;
    }));
    const juce::String import = box->getItemText(box->indexOfItemId(10000));
    CHECK(import.startsWith("Import a file"));
    CHECK(import.contains(".tact"));
    CHECK(box->getDescription().contains(".tact"));
}

TEST_CASE("keyboard only, no screen, no sound: arm feedback waits before the next trial; the answers go to the reader profile; "
          "the adaptive choices; every prompt and feedback spoken and brailled",
          "[plugin][ui][training][reader]")
{
    // The speech is captured to a file (the core's capture backend) and the braille display is a
    // fake BrlAPI server behind the real BrlAPI backend (Tests/Common/FakeBrlApi.h).
    const auto dir = juce::File::createTempFile("armadillo-alone");
    REQUIRE(dir.createDirectory());
    const auto speech = dir.getChildFile("speech.txt");
    const auto profile = dir.getChildFile("reader.json");
    armadillo::test::FakeBrlApiServer server;
    REQUIRE(server.ok());
    setenv("ARMADILLO_SPEECH", ("capture:" + speech.getFullPathName()).toRawUTF8(), 1);
    setenv("ARMADILLO_BRAILLE", ("brlapi:" + server.host()).c_str(), 1);
    App app;
    auto& settings = app.processor->settings();
    settings.setProperty(SettingIds::readerVoice, "on", nullptr);
    if (! app.processor->voice().showing()) {
        WARN("no braille display through libbrlapi here (Debian: libbrlapi0.8): the test needs it");
        return;
    }
    settings.setProperty(SettingIds::armFeedback, true, nullptr);
    settings.setProperty(SettingIds::readerProfile, profile.getFullPathName(), nullptr);

    auto& panel = app.editor->training();
    app.setParam(ParamIds::scene, static_cast<float>(app.sceneIndexOf("braille")));
    app.setParam("braille.mode", static_cast<float>(braille::BrailleMode::Training));
    REQUIRE(pumpUntil([&] { return panel.isShowing() && panel.promptText().isNotEmpty(); }));
    REQUIRE(pumpUntil([&] { return panel.answerField().hasKeyboardFocus(false); }, 2000.0));
    std::string expected0, expected1;
    app.processor->withBrailleTraining([&](braille::BrailleSceneControls& s, std::uint64_t) {
        expected0 = s.trainingExpected(0);
        expected1 = s.trainingExpected(1);
    });
    const juce::String firstPrompt = panel.trialText() + ": " + panel.promptText();

    // A wrong answer, typed and sent with Return: felt on the arm; the next trial waits for it.
    auto& field = panel.answerField();
    const std::string wrong = expected0 == "left" ? "right" : "left";
    field.setText(juce::String(wrong));
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::returnKey)));
    REQUIRE(pumpUntil([&] { return panel.resultText().startsWith("wrong"); }));
    CHECK(app.processor->armFeedbackPlaying());
    CHECK(panel.trialText().startsWith("Trial 1 of"));   // the next trial is not announced yet
    REQUIRE(pumpUntil([&] { return ! app.processor->armFeedbackPlaying(); }, 8000.0));
    REQUIRE(pumpUntil([&] { return panel.trialText().startsWith("Trial 2 of"); }, 2000.0));
    // Right: the arm hums, then the next trial.
    field.setText(juce::String(expected1));
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::returnKey)));
    REQUIRE(pumpUntil([&] { return panel.resultText() == "correct"; }));
    REQUIRE(pumpUntil([&] { return panel.trialText().startsWith("Trial 3 of"); }, 8000.0));

    // Both answers are in the reader profile, as one new session.
    CHECK(panel.recordedAnswers() == 2);
    const auto saved = access::loadReaderProfile(profile.getFullPathName().toStdString());
    REQUIRE(saved.answers.size() == 2);
    CHECK(saved.answers[0].stage == "sides");
    CHECK(saved.answers[0].answer == wrong);
    CHECK_FALSE(saved.answers[0].correct);
    CHECK(saved.answers[1].correct);
    CHECK(saved.sessions.size() == 1);
    // F8 stops the training.
    CHECK(app.press(field, juce::KeyPress(juce::KeyPress::F8Key)));

    // The Reader window's adaptive choices, by keyboard: arrows step the trials and the level,
    // the stages are typed (a bad list refused, said), the method chosen.
    ReaderPanel reader(*app.processor);
    reader.setSize(640, 690);
    reader.addToDesktop(0);
    reader.setVisible(true);
    REQUIRE(pumpUntil([&] { return reader.isShowing(); }));
    auto& trials = reader.trialsControl();
    trials.grabKeyboardFocus();
    CHECK(app.press(trials, juce::KeyPress(juce::KeyPress::downKey)));
    CHECK(static_cast<int>(settings[SettingIds::adaptiveTrials]) == 19);
    app.processor->voice().waitIdle();   // (a new text interrupts one not yet said: each is heard out here)
    for (int i = 0; i < 16; ++i) app.press(trials, juce::KeyPress(juce::KeyPress::downKey));
    CHECK(static_cast<int>(settings[SettingIds::adaptiveTrials]) == 3);
    app.processor->voice().waitIdle();
    auto& stages = reader.stagesControl();
    stages.setText("letters, hold");
    CHECK(reader.takeStages().startsWith("Stages not changed: "));
    app.processor->voice().waitIdle();
    CHECK(settings[SettingIds::adaptiveStages].toString() == "letters,words");
    stages.setText("letters");
    CHECK(reader.takeStages().isEmpty());
    CHECK(settings[SettingIds::adaptiveStages].toString() == "letters");
    app.processor->voice().waitIdle();
    reader.methodControl().setText("dots", juce::sendNotificationSync);
    CHECK(settings[SettingIds::adaptiveMethod].toString() == "dots");

    // The adaptive training with those choices, answered from the keyboard.
    juce::String why;
    REQUIRE(app.processor->beginAdaptive(profile, why));
    auto& answer = reader.adaptiveAnswerField();
    for (int n = 1; n <= 3; ++n) {
        REQUIRE(pumpUntil([&] {
            reader.followForTests();
            return reader.adaptiveStateText().startsWith("Trial " + juce::String(n) + " of 3: ");
        }, 30000.0));
        answer.setText("q");
        CHECK(app.press(answer, juce::KeyPress(juce::KeyPress::returnKey)));
    }
    REQUIRE(pumpUntil([&] { return reader.adaptiveStateText().contains("Training complete"); }, 5000.0));
    const auto log = dir.getChildFile("reader-session2.csv");   // next to the profile: the §4.4.1 training was session 1
    REQUIRE(log.existsAsFile());
    CHECK(log.loadFileAsString().contains(",end,"));
    CHECK(access::loadReaderProfile(profile.getFullPathName().toStdString()).sessions.back().method == "dots");

    // Every prompt and feedback reached the speech and the braille display.
    app.processor->voice().waitIdle();
    // The braille display is written on its own connection, after the speech: wait (event-driven)
    // until the last line reached the display's server.
    auto shownNow = [&] {
        juce::StringArray shown;
        for (const auto& w : server.writes()) shown.add(juce::String(w));
        return shown.joinIntoString("\n");
    };
    pumpUntil([&] { return shownNow().contains("Training complete"); }, 5000.0);
    juce::StringArray said;
    said.addLines(speech.loadFileAsString());
    const auto saidText = said.joinIntoString("\n"), shownText = shownNow();
    for (const juce::String& line : {firstPrompt, juce::String("wrong, it was '" + expected0 + "'"), juce::String("Trial 2 of"),
                                     juce::String("correct"), juce::String("Trials 19"), juce::String("Trials 3"), juce::String("Stages not changed"),
                                     juce::String("Stages letters"), juce::String("Method dots"), juce::String("Trial 1 of 3: "),
                                     juce::String("Training complete")}) {
        INFO(line);
        CHECK(saidText.contains(line));
        CHECK(shownText.contains(line));
    }
    reader.removeFromDesktop();
    unsetenv("ARMADILLO_SPEECH");
    unsetenv("ARMADILLO_BRAILLE");
    dir.deleteRecursively();
}
