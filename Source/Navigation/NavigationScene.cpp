#include "Navigation/NavigationScene.h"
#include "Access/Feedback.h"
#include "Braille/Training.h"
#include "Core/Errors.h"
#include "Core/Pose.h"
#include "Instruments/Scenes.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace armadillo::navigation {

const char* sensationName(Sensation s) noexcept
{
    switch (s) {
    case Sensation::None: return "none";
    case Sensation::Compass: return "compass";
    case Sensation::Arrival: return "arrival";
    case Sensation::OffRoute: return "off-route";
    case Sensation::FixLost: return "fix-lost";
    case Sensation::End: return "end";
    }
    return "?";
}

double thumbHeadingDeg(const core::ArmState& arm, core::ArmSide side) noexcept
{
    if (!arm.valid) return std::numeric_limits<double>::quiet_NaN();
    // The thumb side of the forearm: device −z on the right arm, +z on the left (as the compass).
    const Eigen::Vector3d thumb = arm.q.normalized() * Eigen::Vector3d(0.0, 0.0, side == core::ArmSide::Right ? -1.0 : 1.0);
    if (std::hypot(thumb.x(), thumb.z()) < 0.3) return std::numeric_limits<double>::quiet_NaN();
    return wrap360(std::atan2(thumb.x(), -thumb.z()) * 180.0 / 3.14159265358979323846);   // earth X east, Z south
}

double forearmElevationDeg(const core::ArmState& arm) noexcept
{
    if (!arm.valid) return std::numeric_limits<double>::quiet_NaN();
    const Eigen::Vector3d axis = arm.q.normalized() * Eigen::Vector3d::UnitX();   // device x: toward the hand
    return std::asin(std::clamp(axis.y(), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;   // earth Y up
}

std::string shownName(const std::string& name, NameDisplay mode, const std::vector<std::pair<std::string, std::string>>& shorthand)
{
    if (mode == NameDisplay::None) return {};
    std::string lower;
    for (unsigned char c : name) lower += static_cast<char>(std::tolower(c));
    if (mode == NameDisplay::Shorthand) {
        std::string letters;
        for (char c : lower)
            if (c >= 'a' && c <= 'z') letters += c;
        for (const auto& [abbrev, word] : shorthand)
            if (word == letters) return abbrev;
    }
    return lower;
}

namespace {

using access::TactileSegment;
constexpr std::uint16_t kAll = 0x1FF;
constexpr std::uint16_t kCorners = (1u << 0) | (1u << 2) | (1u << 6) | (1u << 8);
constexpr int kCompassTarget = 0;   // "compass.target", the compass scene's first parameter
constexpr double kMagDisturbedS = 0.5;   // s of refused magnetometer samples before the learning pauses

double endOf(const std::vector<TactileSegment>& s)
{
    double e = 0.0;
    for (const auto& x : s) e = std::max(e, x.at + x.duration);
    return e;
}

void append(std::vector<TactileSegment>& to, const std::vector<TactileSegment>& from)
{
    to.insert(to.end(), from.begin(), from.end());
}

/// Arrival: all nine motors three times, short and firm — nothing else on the arm feels like it.
std::vector<TactileSegment> arrivalSensation(float level)
{
    return {{0.00, 0.12, kAll, level, false, false}, {0.24, 0.12, kAll, level, false, false}, {0.48, 0.12, kAll, level, false, false}};
}

/// The route's end: two long soft swells of the whole grid.
std::vector<TactileSegment> endSensation(float level, double at)
{
    return {{at, 1.0, kAll, level * 0.8f, true, false}, {at + 1.4, 1.0, kAll, level * 0.8f, true, false}};
}

/// Off route: the four corners, four quick taps (no braille row lights two corners at once).
std::vector<TactileSegment> offRouteSensation(float level)
{
    std::vector<TactileSegment> s;
    for (int i = 0; i < 4; ++i) s.push_back({0.2 * i, 0.1, kCorners, level, false, false});
    return s;
}

class NavigationScene final : public core::Scene {
public:
    NavigationScene(const Route& route, std::shared_ptr<NavigationLink> link, const NavigationOptions& options)
        : route_(route), link_(std::move(link)), options_(options), guidance_(route, options.guidance), learner_(options.heading),
          compass_(instruments::makeCompassScene())
    {
        if (route_.points.size() < 2) throw core::InputError(route_.source, 0, "", "a route needs at least 2 points");
        if (!link_) throw std::invalid_argument("makeNavigationScene: no NavigationLink");
        plane_.origin = route_.points.front().pos;
    }
    std::string_view name() const override { return "navigate"; }

    void prepare(const core::SceneConfig& config) override
    {
        side_ = config.side;
        compass_->prepare(config);
        compass_->setParameter(1, 5.0f);                           // compass.tolerance, deg (§4.1's figure)
        compass_->setParameter(2, std::clamp(options_.level, 0.0f, 15.0f));   // compass.level
        const std::vector<std::string> words = options_.signWords.empty() ? braille::defaultSignWords(config.resourceDir) : options_.signWords;
        const auto shorthand = braille::signShorthand(words);
        const float level = std::clamp(options_.level, 0.0f, 15.0f);
        sequences_.assign(route_.points.size(), {});
        shown_.assign(route_.points.size(), {});
        for (std::size_t i = 1; i < route_.points.size(); ++i) {
            std::vector<TactileSegment> seq = arrivalSensation(level);
            std::string text = shownName(route_.points[i].name, options_.names, shorthand);
            double at = endOf(seq) + 0.5;
            if (!text.empty()) {
                // Framed as the adaptive training frames a cell (Access/Feedback.h): the "next"
                // sweep, the cells by the rows method, the "your turn" double tap.
                std::vector<TactileSegment> cells;
                double end = 0.0;
                try {
                    cells = access::drawnText(text, 1, braille::DisplayMethod::Rows, level, at + 0.5, end, 400);
                } catch (const core::InputError&) { // a character liblouis cannot show: letters and spaces only
                    std::string plain;
                    for (char c : text)
                        if ((c >= 'a' && c <= 'z') || c == ' ') plain += c;
                    text = plain;
                    cells = text.empty() ? std::vector<TactileSegment> {} : access::drawnText(text, 1, braille::DisplayMethod::Rows, level, at + 0.5, end, 400);
                }
                if (!cells.empty()) {
                    append(seq, access::nextCue(level, at));
                    append(seq, cells);
                    append(seq, access::yourTurnCue(level, end));
                }
            }
            if (i + 1 == route_.points.size()) append(seq, endSensation(level, endOf(seq) + 0.6));
            std::sort(seq.begin(), seq.end(), [](const TactileSegment& a, const TactileSegment& b) { return a.at < b.at; });
            sequences_[i] = std::move(seq);
            shown_[i] = text.substr(0, kMaxWaypointName);
        }
        offRoute_ = offRouteSensation(level);
        guidance_.reset();   // the walk starts here: the route from its start, nothing learned yet
        learner_.reset();
        t_ = 0.0;
        arrivals_ = 0;
        reset();
    }

    /// Entering the scene or resuming after a panic (Engine::resume): what was being shown is
    /// dropped, the walk is not — the waypoint reached and the learned offset stay.
    void reset() override
    {
        compass_->reset();
        mode_ = Mode::Enter;
        playing_ = nullptr;
        levels_.fill(-1.0f);
    }

    void control(const core::ControlInput& in, core::SceneOutput& out) override
    {
        const double dt = std::isfinite(in.dt) && in.dt > 0.0 ? in.dt : 0.0;
        t_ += dt;
        const PositionFix report = link_->position.latest();
        const GuidanceStep g = guidance_.step(dt, report);

        const double armHeading = thumbHeadingDeg(in.arm, side_);
        // The fusion's magnetic-disturbance detection (Fusion/Trackers.h): while the field is
        // refused the heading rests on the gyro, good for the compass a while but not to learn a
        // strap offset from (a local steel bias would be learned as the strap's).
        const bool magDisturbed = in.arm.magDisturbedS > kMagDisturbedS;
        if (magDisturbed) {
            learner_.breakFit();
        } else {
            learner_.arm(t_, armHeading, forearmElevationDeg(in.arm));
            if (g.newFix) {
                double x = 0.0, y = 0.0;
                plane_.toXY(guidance_.lastFix().pos, x, y);
                learner_.fix(t_, x, y, guidance_.lastFix().courseDeg, guidance_.lastFix().speedMps);
            }
        }
        if (g.fixLostNow) learner_.breakFit();
        const double offset = options_.learnHeading && learner_.learned() ? learner_.offsetDeg() : options_.headingOffsetDeg;
        const double heading = std::isfinite(armHeading) ? wrap360(armHeading - offset) : armHeading;

        // Events start a sequence; an arrival outranks an off-route reminder.
        if (g.arrivedAt > 0) {
            ++arrivals_;
            start(&sequences_[static_cast<std::size_t>(g.arrivedAt - 1)], Sensation::Arrival);
        } else if (g.offRouteCue && playing_ == nullptr) {
            start(&offRoute_, Sensation::OffRoute);
        }

        Sensation felt = Sensation::None;
        if (playing_ != nullptr) {
            enter(Mode::Sequence, out);
            felt = playingKind_;
            if (!play(out)) playing_ = nullptr;
        }
        if (playing_ == nullptr) {
            if (g.finished) {
                enter(Mode::Idle, out);
            } else if (g.fix != FixState::Ok) {
                if (enter(Mode::Lost, out)) {
                    // Fix lost (or none yet): the centre motor swells slowly, and no direction is shown.
                    core::PatternRequest breathe;
                    breathe.kind = core::PatternKind::Breathing;
                    breathe.motors = static_cast<std::uint16_t>(1u << 4);
                    breathe.level = std::clamp(options_.level, 0.0f, 15.0f) * 0.8f;
                    breathe.rate = 0.5;
                    breathe.duration = -1.0;
                    breathe.voice = 1;
                    breathe.soft = true;
                    out.motors.trigger(breathe);
                }
                felt = Sensation::FixLost;
            } else {
                enter(Mode::Compass, out);
                // The compass scene compares its target with the raw thumb heading; corrected
                // heading = raw − offset, so aiming it at bearing + offset shows bearing − corrected.
                compass_->setParameter(kCompassTarget, static_cast<float>(wrap360(g.bearingDeg + offset)));
                compass_->control(in, out);
                felt = Sensation::Compass;
            }
        }
        publish(g, heading, armHeading, offset, felt, magDisturbed);
    }

private:
    enum class Mode { Enter, Compass, Sequence, Lost, Idle };

    /// Switches the display mode; true when it changed (everything of the old mode stopped).
    bool enter(Mode m, core::SceneOutput& out) noexcept
    {
        if (m == mode_) return false;
        out.motors.stopVoice(0);
        out.motors.stopVoice(1);
        out.motors.clearLevels();
        levels_.fill(0.0f);
        if (m == Mode::Compass) compass_->reset();   // it starts afresh (clears what it showed)
        mode_ = m;
        return true;
    }

    void start(const std::vector<TactileSegment>* seq, Sensation kind) noexcept
    {
        if (seq->empty()) return;
        playing_ = seq;
        playingKind_ = kind == Sensation::Arrival && seq == &sequences_.back() ? Sensation::End : kind;
        seqT_ = 0.0;
        startT_ = t_;
        if (mode_ == Mode::Sequence) mode_ = Mode::Enter;   // a new sequence clears the old one's motors
    }

    /// One step of the playing sequence; false once it is over.
    bool play(core::SceneOutput& out) noexcept
    {
        seqT_ = t_ - startT_;
        std::array<float, core::kGridMotors> want {};
        std::array<bool, core::kGridMotors> soft {};
        double endAt = 0.0;
        for (const TactileSegment& s : *playing_) {
            endAt = std::max(endAt, s.at + s.duration);
            if (seqT_ < s.at || seqT_ >= s.at + s.duration) continue;
            for (int m = 0; m < core::kGridMotors; ++m) {
                if (!(s.motors & (1u << m))) continue;
                if (s.level > want[static_cast<std::size_t>(m)]) {
                    want[static_cast<std::size_t>(m)] = s.level;
                    soft[static_cast<std::size_t>(m)] = s.soft;
                }
            }
        }
        for (int m = 0; m < core::kGridMotors; ++m) {
            const auto i = static_cast<std::size_t>(m);
            if (want[i] == levels_[i]) continue;
            if (soft[i]) out.motors.setSoftLevel(m, want[i]);
            else out.motors.setLevel(m, want[i]);
            levels_[i] = want[i];
        }
        return seqT_ < endAt;
    }

    void publish(const GuidanceStep& g, double heading, double armHeading, double offset, Sensation felt, bool magDisturbed) noexcept
    {
        NavigationStatus s;
        s.t = t_;
        s.waypoint = g.waypoint;
        s.waypointCount = static_cast<int>(route_.points.size());
        if (g.waypoint >= 1 && g.waypoint <= s.waypointCount) {
            const auto i = static_cast<std::size_t>(g.waypoint - 1);
            std::strncpy(s.name, route_.points[i].name.c_str(), kMaxWaypointName);
            std::strncpy(s.shown, shown_[i].c_str(), kMaxWaypointName);
        }
        s.distanceM = g.distanceM;
        s.bearingDeg = g.bearingDeg;
        s.headingDeg = heading;
        s.offsetDeg = offset;
        s.headingLearned = options_.learnHeading && learner_.learned();
        s.fix = g.fix;
        if (g.fix != FixState::Waiting && validLatLon(guidance_.lastFix().pos) && guidance_.lastFix().serial != 0) {
            s.lat = guidance_.lastFix().pos.lat;
            s.lon = guidance_.lastFix().pos.lon;
            s.accuracyM = guidance_.lastFix().accuracyM;
        }
        s.offRoute = g.offRoute;
        s.finished = g.finished;
        s.arrivals = arrivals_;
        s.sensation = felt;
        s.magDisturbed = magDisturbed;
        link_->status.store(s);
        if (!link_->logEnabled.load(std::memory_order_relaxed)) return;
        NavigationLogRecord r;
        r.t = t_;
        r.lat = s.lat;
        r.lon = s.lon;
        r.fix = g.fix;
        r.waypoint = g.waypoint;
        r.distanceM = g.distanceM;
        r.bearingDeg = g.bearingDeg;
        r.headingDeg = heading;
        r.armHeadingDeg = armHeading;
        r.offsetDeg = offset;
        r.legDistanceM = g.legDistanceM;
        r.offRoute = g.offRoute;
        r.arrivedAt = g.arrivedAt;
        r.sensation = felt;
        r.magDisturbed = magDisturbed;
        if (!link_->log.push(r)) link_->droppedLog.fetch_add(1, std::memory_order_relaxed);
    }

    Route route_;
    std::shared_ptr<NavigationLink> link_;
    NavigationOptions options_;
    Guidance guidance_;
    HeadingLearner learner_;
    std::unique_ptr<core::Scene> compass_;
    LocalPlane plane_ {};
    core::ArmSide side_ = core::ArmSide::Right;
    std::vector<std::vector<TactileSegment>> sequences_;   // per route point: arrival + name (+ end for the last)
    std::vector<std::string> shown_;
    std::vector<TactileSegment> offRoute_;
    const std::vector<TactileSegment>* playing_ = nullptr;
    Sensation playingKind_ = Sensation::None;
    double t_ = 0.0, seqT_ = 0.0, startT_ = 0.0;
    Mode mode_ = Mode::Enter;
    std::array<float, core::kGridMotors> levels_ {};
    int arrivals_ = 0;
};

} // namespace

std::unique_ptr<core::Scene> makeNavigationScene(const Route& route, std::shared_ptr<NavigationLink> link, const NavigationOptions& options)
{
    return std::make_unique<NavigationScene>(route, std::move(link), options);
}

} // namespace armadillo::navigation
