#include "Plugin/ArmView.h"
#include "Plugin/PluginProcessor.h"
#include <cmath>

namespace armadillo::plugin {

namespace {
const juce::Colour kBackground {0xff10141a};
const juce::Colour kGrid {0xff5a6b7d};
const juce::Colour kArm {0xfff2b24c};
const juce::Colour kNormal {0xff6fd3ff};
const juce::Colour kFret {0xff8ee07a};
const juce::Colour kCymbal {0xffd9b44a};

Eigen::Vector3d directionFor(double elevationDeg, double azimuthDeg)
{
    // Heading clockwise from north (−Z) toward east (+X); elevation above the horizon (+Y).
    const double e = core::degToRad(elevationDeg), a = core::degToRad(azimuthDeg);
    return {std::sin(a) * std::cos(e), std::sin(e), -std::cos(a) * std::cos(e)};
}

class PoseValue : public juce::AccessibilityTextValueInterface {
public:
    explicit PoseValue(ArmView& view) : view_(view) {}
    bool isReadOnly() const override { return true; }
    juce::String getCurrentValueAsString() const override { return view_.describePose(); }
    void setValueAsString(const juce::String&) override {}

private:
    ArmView& view_;
};
} // namespace

ArmView::ArmView(ArmadilloProcessor& processor) : processor_(processor)
{
    setTitle("Arm view");
    setDescription("The forearm on the environment sphere, seen from behind the performer. "
                   "Arrow keys or a mouse drag move the arm (simulator or host automation source); "
                   "comma and full stop roll it; W resumes wandering; Shift with arrows or a right-drag "
                   "turns the camera.");
    setWantsKeyboardFocus(true);
    setOpaque(true);
    startTimerHz(30);
}

ArmView::~ArmView() = default;

std::unique_ptr<juce::AccessibilityHandler> ArmView::createAccessibilityHandler()
{
    return std::make_unique<juce::AccessibilityHandler>(
        *this, juce::AccessibilityRole::image, juce::AccessibilityActions {},
        juce::AccessibilityHandler::Interfaces {std::make_unique<PoseValue>(*this)});
}

void ArmView::timerCallback()
{
    const auto f = processor_.latestFrame();
    const Eigen::Quaterniond q(f.q[0], f.q[1], f.q[2], f.q[3]);
    valid_ = f.valid;
    if (! valid_) {
        repaint();
        return;
    }
    q_ = q.normalized();
    trail_.push_back(q_ * Eigen::Vector3d::UnitX());
    while (trail_.size() > 90) trail_.pop_front();   // 3 s of tip path at 30 Hz
    repaint();
}

juce::String ArmView::describePose() const
{
    if (! valid_) return "No orientation yet";
    const auto p = core::quaternionToPose(q_);
    return "Elevation " + juce::String(juce::roundToInt(p.elevationDeg)) + " degrees, azimuth "
           + juce::String(juce::roundToInt(p.azimuthDeg)) + " degrees, roll " + juce::String(juce::roundToInt(p.rollDeg))
           + " degrees";
}

ArmView::Projected ArmView::project(const Eigen::Vector3d& w) const
{
    // Turn about Y by the camera azimuth, then tilt about X by its elevation (looking down).
    const double a = core::degToRad(cameraAzimuthDeg_), e = core::degToRad(cameraElevationDeg_);
    const double x1 = w.x() * std::cos(a) - w.z() * std::sin(a);
    const double z1 = w.x() * std::sin(a) + w.z() * std::cos(a);
    const double y2 = w.y() * std::cos(e) - z1 * std::sin(e);
    const double z2 = w.y() * std::sin(e) + z1 * std::cos(e);
    return {{centre_.x + radius_ * static_cast<float>(x1), centre_.y - radius_ * static_cast<float>(y2)},
            static_cast<float>(z2)};
}

bool ArmView::unproject(juce::Point<float> s, Eigen::Vector3d& w) const
{
    const double x1 = (s.x - centre_.x) / radius_;
    const double y2 = (centre_.y - s.y) / radius_;
    const double rr = x1 * x1 + y2 * y2;
    if (rr > 1.0) return false;
    const double z2 = std::sqrt(1.0 - rr);   // the front hemisphere: the one the user sees
    const double a = core::degToRad(cameraAzimuthDeg_), e = core::degToRad(cameraElevationDeg_);
    const double y = y2 * std::cos(e) + z2 * std::sin(e);
    const double z1 = -y2 * std::sin(e) + z2 * std::cos(e);
    const double x = x1 * std::cos(a) + z1 * std::sin(a);
    const double z = -x1 * std::sin(a) + z1 * std::cos(a);
    w = Eigen::Vector3d(x, y, z);
    return true;
}

void ArmView::drawCircle(juce::Graphics& g, const std::vector<Eigen::Vector3d>& pts, juce::Colour c, float width,
                         bool closed) const
{
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i + (closed ? 0 : 1) < n; ++i) {
        const auto a = project(pts[i]);
        const auto b = project(pts[(i + 1) % n]);
        const bool front = a.depth + b.depth >= 0.0f;
        g.setColour(front ? c : c.withMultipliedAlpha(0.3f));
        g.drawLine({a.p, b.p}, front ? width : width * 0.7f);
    }
}

void ArmView::drawLatitude(juce::Graphics& g, double elevationDeg, juce::Colour c, float width) const
{
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 72; ++i) pts.push_back(directionFor(elevationDeg, i * 5.0));
    drawCircle(g, pts, c, width);
}

float ArmView::paramValue(const char* id, float fallback) const
{
    if (auto* v = processor_.parameters().getRawParameterValue(id)) return v->load();
    return fallback;
}

void ArmView::drawSceneObjects(juce::Graphics& g) const
{
    const auto& scenes = processor_.sceneTable().scenes;
    const int index = processor_.sceneIndex();
    if (index < 0 || index >= static_cast<int>(scenes.size())) return;
    const auto& name = scenes[static_cast<std::size_t>(index)].scene;
    const float labelSize = std::max(11.0f, radius_ * 0.045f);
    g.setFont(labelSize);
    if (name == "theremin") {
        // Thesis §3.5: pitch linear in sin(elevation); frets on the A-major scale.
        const double bottom = core::degToRad(paramValue("theremin.bottom", -45.0f));
        const double top = core::degToRad(paramValue("theremin.top", 45.0f));
        const double range = std::max(1.0f, paramValue("theremin.range", 12.0f));
        static const char* names[] {"A", "B", "C#", "D", "E", "F#", "G#", "A"};
        static const int steps[] {0, 2, 4, 5, 7, 9, 11, 12};
        for (int i = 0; i < 8; ++i) {
            if (steps[i] > range) break;
            const double y = std::sin(bottom) + (std::sin(top) - std::sin(bottom)) * steps[i] / range;
            if (y < -1.0 || y > 1.0) continue;
            const double elev = core::radToDeg(std::asin(y));
            drawLatitude(g, elev, kFret.withAlpha(0.85f), 1.6f);
            // Labels on the left limb, away from the compass letters.
            const auto label = project(directionFor(elev, -90.0 - cameraAzimuthDeg_));
            g.setColour(kFret);
            g.drawText(names[i], juce::Rectangle<float>(labelSize * 2.5f, labelSize * 1.2f).withCentre(label.p - juce::Point<float>(labelSize * 1.6f, 0.0f)),
                       juce::Justification::centredRight);
        }
    } else if (name == "cymbal") {
        // Thesis §3.6: the cymbal lies below its surface elevation; draw the surface as a disc.
        const double surface = paramValue("cymbal.surface", 0.0f);
        juce::Path disc;
        for (int i = 0; i < 72; ++i) {
            const auto p = project(directionFor(surface, i * 5.0) * std::cos(0.0)).p;
            if (i == 0) disc.startNewSubPath(p);
            else disc.lineTo(p);
        }
        disc.closeSubPath();
        g.setColour(kCymbal.withAlpha(0.22f));
        g.fillPath(disc);
        drawLatitude(g, surface, kCymbal, 2.0f);
        g.setColour(kCymbal);
        g.drawText("cymbal surface", juce::Rectangle<float>(radius_, labelSize * 1.3f).withCentre(project(directionFor(surface - 8.0, 180.0 - cameraAzimuthDeg_)).p),
                   juce::Justification::centred);
    } else if (name == "panel") {
        // Thesis §3.4: two knob levels, 30° above and below the horizon.
        drawLatitude(g, 30.0, kFret.withAlpha(0.8f), 1.5f);
        drawLatitude(g, -30.0, kFret.withAlpha(0.8f), 1.5f);
    } else if (name == "compass") {
        for (const auto& entry : scenes)
            if (entry.scene == "compass")
                for (const auto& spec : entry.specs)
                    if (spec.id.find("target") != std::string::npos) {
                        const double heading = paramValue(spec.id.c_str(), 0.0f);
                        std::vector<Eigen::Vector3d> meridian;
                        for (int e = -80; e <= 80; e += 5) meridian.push_back(directionFor(e, heading));
                        drawCircle(g, meridian, kFret, 2.0f, false);
                    }
    }
}

void ArmView::paint(juce::Graphics& g)
{
    g.fillAll(kBackground);
    auto area = getLocalBounds().toFloat().reduced(8.0f);
    centre_ = area.getCentre();
    radius_ = 0.44f * std::min(area.getWidth(), area.getHeight());

    // Sphere: outline, latitudes every 30°, meridians every 30°.
    g.setColour(juce::Colour(0xff18202a));
    g.fillEllipse(juce::Rectangle<float>(2.0f * radius_, 2.0f * radius_).withCentre(centre_));
    g.setColour(kGrid);
    g.drawEllipse(juce::Rectangle<float>(2.0f * radius_, 2.0f * radius_).withCentre(centre_), 1.2f);
    for (int e = -60; e <= 60; e += 30) drawLatitude(g, e, kGrid.withAlpha(e == 0 ? 0.9f : 0.45f), e == 0 ? 1.4f : 0.8f);
    for (int a = 0; a < 360; a += 30) {
        std::vector<Eigen::Vector3d> m;
        for (int e = -90; e <= 90; e += 5) m.push_back(directionFor(e, a));
        drawCircle(g, m, kGrid.withAlpha(0.3f), 0.7f, false);
    }
    const float labelSize = std::max(12.0f, radius_ * 0.05f);
    g.setFont(juce::Font(labelSize, juce::Font::bold));
    const char* compass[] {"N", "E", "S", "W"};
    for (int i = 0; i < 4; ++i) {
        const auto p = project(directionFor(0.0, i * 90.0) * 1.08);
        g.setColour(kGrid.brighter(p.depth >= 0.0f ? 0.8f : 0.0f).withAlpha(p.depth >= 0.0f ? 1.0f : 0.5f));
        g.drawText(compass[i], juce::Rectangle<float>(labelSize * 2.0f, labelSize * 1.4f).withCentre(p.p), juce::Justification::centred);
    }

    drawSceneObjects(g);

    if (valid_) {
        // Trail of the hand's path, then the forearm from the elbow (centre) to the hand.
        for (std::size_t i = 1; i < trail_.size(); ++i) {
            const auto a = project(trail_[i - 1]), b = project(trail_[i]);
            g.setColour(kArm.withAlpha(0.1f + 0.5f * static_cast<float>(i) / static_cast<float>(trail_.size())));
            g.drawLine({a.p, b.p}, 1.5f);
        }
        const Eigen::Vector3d axis = q_ * Eigen::Vector3d::UnitX();
        const Eigen::Vector3d normal = q_ * Eigen::Vector3d::UnitY();
        const Eigen::Vector3d edge = q_ * Eigen::Vector3d::UnitZ();
        const auto elbow = project(Eigen::Vector3d::Zero());
        const auto hand = project(axis);
        const float w = std::max(3.0f, radius_ * 0.035f);
        // The forearm as a band: width along the edge normal, so roll is visible.
        juce::Path band;
        const auto e0 = project(edge * 0.08), e1 = project(-edge * 0.08);
        const auto h0 = project(axis + edge * 0.05), h1 = project(axis - edge * 0.05);
        band.startNewSubPath(e0.p);
        band.lineTo(h0.p);
        band.lineTo(h1.p);
        band.lineTo(e1.p);
        band.closeSubPath();
        g.setColour(kArm.withAlpha(hand.depth >= 0.0f ? 0.85f : 0.55f));
        g.fillPath(band);
        g.setColour(kArm.brighter(0.3f));
        g.drawLine({elbow.p, hand.p}, 1.5f);
        // The board's face normal at the middle of the forearm (thesis §2.6.3).
        const auto mid = project(axis * 0.6);
        const auto tip = project(axis * 0.6 + normal * 0.22);
        g.setColour(kNormal);
        g.drawArrow({mid.p, tip.p}, 2.0f, w * 1.6f, w * 1.4f);
        g.setColour(kArm);
        g.fillEllipse(juce::Rectangle<float>(w * 2.2f, w * 2.2f).withCentre(hand.p));
    }

    g.setColour(juce::Colours::white.withAlpha(0.9f));
    g.setFont(std::max(12.0f, radius_ * 0.045f));
    g.drawFittedText(describePose(), getLocalBounds().reduced(10).removeFromTop(24), juce::Justification::topLeft, 1);
    if (hasKeyboardFocus(false)) {
        g.setColour(kNormal);
        g.drawRect(getLocalBounds(), 2);
    }
}

core::Pose ArmView::currentPose() const
{
    return valid_ ? core::quaternionToPose(q_) : core::Pose {};
}

void ArmView::moveArm(const core::Pose& pose)
{
    switch (processor_.source()) {
    case SourceKind::Simulator: processor_.steerSimulator(pose); break;
    case SourceKind::HostAutomation: processor_.setOrientationFromUser(pose); break;
    default: break;   // device and OSC own the arm
    }
}

void ArmView::mouseDown(const juce::MouseEvent& e)
{
    grabKeyboardFocus();
    lastDrag_ = e.position;
    if (! e.mods.isRightButtonDown() && ! e.mods.isShiftDown()) mouseDrag(e);
}

void ArmView::mouseDrag(const juce::MouseEvent& e)
{
    if (e.mods.isRightButtonDown() || e.mods.isShiftDown()) {
        const auto d = e.position - lastDrag_;
        cameraAzimuthDeg_ = core::wrapDeg360(cameraAzimuthDeg_ + d.x * 0.4);
        cameraElevationDeg_ = juce::jlimit(-80.0, 80.0, cameraElevationDeg_ + d.y * 0.4);
        lastDrag_ = e.position;
        repaint();
        return;
    }
    Eigen::Vector3d w;
    if (! unproject(e.position, w)) return;
    core::Pose p = currentPose();
    p.elevationDeg = core::radToDeg(std::asin(juce::jlimit(-1.0, 1.0, w.y())));
    p.azimuthDeg = core::wrapDeg360(core::radToDeg(std::atan2(w.x(), -w.z())));
    moveArm(p);
}

bool ArmView::keyPressed(const juce::KeyPress& key)
{
    const bool shift = key.getModifiers().isShiftDown();
    const int code = key.getKeyCode();
    if (shift && (code == juce::KeyPress::leftKey || code == juce::KeyPress::rightKey || code == juce::KeyPress::upKey
                  || code == juce::KeyPress::downKey)) {
        if (code == juce::KeyPress::leftKey) cameraAzimuthDeg_ = core::wrapDeg360(cameraAzimuthDeg_ - 10.0);
        if (code == juce::KeyPress::rightKey) cameraAzimuthDeg_ = core::wrapDeg360(cameraAzimuthDeg_ + 10.0);
        if (code == juce::KeyPress::upKey) cameraElevationDeg_ = juce::jlimit(-80.0, 80.0, cameraElevationDeg_ + 10.0);
        if (code == juce::KeyPress::downKey) cameraElevationDeg_ = juce::jlimit(-80.0, 80.0, cameraElevationDeg_ - 10.0);
        repaint();
        return true;
    }
    core::Pose p = currentPose();
    if (code == juce::KeyPress::upKey) p.elevationDeg = std::min(90.0, p.elevationDeg + 5.0);
    else if (code == juce::KeyPress::downKey) p.elevationDeg = std::max(-90.0, p.elevationDeg - 5.0);
    else if (code == juce::KeyPress::leftKey) p.azimuthDeg = core::wrapDeg360(p.azimuthDeg - 5.0);
    else if (code == juce::KeyPress::rightKey) p.azimuthDeg = core::wrapDeg360(p.azimuthDeg + 5.0);
    else if (key.getTextCharacter() == ',') p.rollDeg = core::wrapDeg180(p.rollDeg - 10.0);
    else if (key.getTextCharacter() == '.') p.rollDeg = core::wrapDeg180(p.rollDeg + 10.0);
    else if (key.getTextCharacter() == 'w' || key.getTextCharacter() == 'W') {
        processor_.setSimulatorWandering(true);
        return true;
    } else return false;
    moveArm(p);
    return true;
}

} // namespace armadillo::plugin
