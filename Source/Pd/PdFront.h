#pragma once
// What Pure Data's [armadillo] and [armadillo~] share (issue 46; docs/PUREDATA.md,
// docs/INTERFACES.md "Pure Data objects"); with the two objects' files, the only code that
// includes m_pd.h. Both objects are presenters of the one
// instrument: they turn Pd messages into Commands (Pd/Commands.h), and on Pd's own thread — a Pd
// clock every control period — turn what the instrument published into outlet messages.
// [armadillo] drives live::LiveSession on its source's clock (Pd/SessionInstrument.h);
// [armadillo~]'s DSP method clocks live::BlockInstrument's control step with Pd's DSP blocks
// (Pd/BlockHost.h), as a plugin host's blocks clock the plugin's. No control loop is run here.
//
// One library holds both classes and is installed under both names (armadillo.pd_linux and
// armadillo~.pd_linux: Pd finds an object by its file name); either setup function registers
// both classes, once (`[declare -lib armadillo]` then gives both from Pd's extra folder).
#include "Pd/Commands.h"
#include <m_pd.h>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace armadillo::pd {

inline constexpr double kPollMs = 5.0;        // the control period: 200 Hz
inline constexpr double kStatusMs = 1000.0;   // `status` once a second (and on bang)

/// A method of ours as Pd's generic method pointer (Pd calls it with the arguments it was
/// declared with; the cast through void (*)() says so without a warning).
template <typename F> t_method method(F f) { return reinterpret_cast<t_method>(reinterpret_cast<void (*)()>(f)); }
template <typename F> t_newmethod newMethod(F f) { return reinterpret_cast<t_newmethod>(reinterpret_cast<void (*)()>(f)); }

inline std::vector<Atom> atoms(int argc, const t_atom* argv)
{
    std::vector<Atom> out;
    for (int i = 0; i < argc; ++i) {
        if (argv[i].a_type == A_FLOAT) out.emplace_back(static_cast<double>(atom_getfloat(&argv[i])));
        else if (argv[i].a_type == A_SYMBOL) out.emplace_back(std::string(atom_getsymbol(&argv[i])->s_name));
        else out.emplace_back(std::string("?"));
    }
    return out;
}

inline std::string said(const std::exception& e)
{
    std::string what = e.what();
    const std::string anonymous = "<input>: ";
    if (what.compare(0, anonymous.size(), anonymous) == 0) what.erase(0, anonymous.size());
    return what;
}

/// What both objects share: the commands, the outlet for messages, the output clock.
struct Front {
    Instrument& instrument;
    Commands commands;
    t_outlet* out = nullptr;
    t_clock* clock = nullptr;
    double lastStatus = 0.0;
    std::uint64_t stepsAtStatus = 0;
    double rateHz = 0.0;

    Front(Instrument& i, const std::string& dir) : instrument(i), commands(i, dir, std::make_shared<core::MotorTargets>()) {}

    void send(const char* selector, const t_float* values, int n)
    {
        t_atom a[core::kMaxMotors];
        for (int i = 0; i < n; ++i) SETFLOAT(&a[i], values[i]);
        outlet_anything(out, gensym(selector), n, a);
    }
    void sendStatus()
    {
        const double elapsed = clock_gettimesince(lastStatus);
        const std::uint64_t steps = instrument.controlSteps();
        if (elapsed > 0.0 && steps >= stepsAtStatus) rateHz = static_cast<double>(steps - stepsAtStatus) * 1000.0 / elapsed;
        if (steps < stepsAtStatus) rateHz = 0.0;   // a new source counts from zero
        stepsAtStatus = steps;
        lastStatus = clock_getlogicaltime();
        const Status s = instrument.status();
        t_atom a[4];
        SETSYMBOL(&a[0], gensym(s.source.c_str()));
        SETSYMBOL(&a[1], gensym(s.connection.c_str()));
        SETFLOAT(&a[2], static_cast<t_float>(s.source == "none" ? 0.0 : rateHz));
        SETFLOAT(&a[3], static_cast<t_float>(s.dropped));
        outlet_anything(out, gensym("status"), 4, a);
    }
    /// The clock: what the instrument published since the last tick, then the next tick.
    void present()
    {
        Frame f;
        if (instrument.poll(f)) {
            if (f.valid) {
                const t_float q[4] = {t_float(f.q[0]), t_float(f.q[1]), t_float(f.q[2]), t_float(f.q[3])};
                send("quaternion", q, 4);
                const t_float pose[3] = {t_float(f.pose[0]), t_float(f.pose[1]), t_float(f.pose[2])};
                send("orientation", pose, 3);
            }
            t_float m[core::kMaxMotors];
            const int n = f.motorCount < core::kMaxMotors ? f.motorCount : core::kMaxMotors;
            for (int i = 0; i < n; ++i) m[i] = f.motors[static_cast<std::size_t>(i)];
            send("motors", m, n);
        }
        std::string gesture;
        while (instrument.nextGesture(gesture)) {
            t_atom a;
            SETSYMBOL(&a, gensym(gesture.c_str()));
            outlet_anything(out, gensym("gesture"), 1, &a);
        }
        if (clock_gettimesince(lastStatus) >= kStatusMs) sendStatus();
        clock_delay(clock, kPollMs);
    }
    /// One inlet message: handled, or answered with pd_error naming the problem.
    void message(void* owner, const char* name, t_symbol* s, int argc, t_atom* argv)
    {
        try {
            if (commands.handle(s->s_name, atoms(argc, argv))) sendStatus();
        } catch (const std::exception& e) {
            pd_error(owner, "%s: %s", name, said(e).c_str());
        }
    }
};

/// Each class registered with Pd unless it already is (ArmadilloObject.cpp, ArmadilloTildeObject.cpp).
void registerArmadillo();
void registerArmadilloTilde();

} // namespace armadillo::pd
