// `armadillo mqtt check`: is the broker there, and what is said on a topic? (docs/MQTT.md)
#include "Cli/CommandLine.h"
#include "Cli/Commands.h"
#include "Cli/MqttOptions.h"
#include "Core/Errors.h"
#include "Core/Json.h"
#include "Core/Types.h"
#include "Mqtt/BrokerCheck.h"
#include <iostream>

namespace armadillo::cli {

namespace {

int check(const CommandLine& cl)
{
    mqtt::MqttConfig config;
    if (!readMqttOptions(cl, config, cl.has("--broker") ? "--broker" : "--mqtt")) throw UsageError("mqtt check needs a broker: --broker HOST[:PORT] (or --mqtt-config FILE)");
    for (const std::string& t : cl.values("--topic")) {
        if (const std::string why = mqtt::topicFilterProblem(t); !why.empty()) throw UsageError("--topic '" + t + "': " + why);
        config.topics.push_back({t, 1, false});
    }
    if (config.topics.empty()) config.topics.push_back({"#", 0, false});   // everything the broker lets us see
    const double timeout = cl.number("--timeout", 5.0);
    const double seconds = cl.number("--seconds", 5.0);
    if (!(timeout > 0.0 && timeout <= 600.0)) throw UsageError("--timeout must lie in (0, 600] s");
    if (!(seconds >= 0.0 && seconds <= 86400.0)) throw UsageError("--seconds must lie in 0..86400 s");
    const long maxCount = cl.integer("--count", 0, 0, 1000000);

    mqtt::BrokerCheckOptions options;
    options.timeout = timeout;
    options.seconds = seconds;
    options.maxCount = maxCount;
    if (cl.has("--publish")) {
        if (config.topics.size() != 1 || config.topics[0].filter.find_first_of("+#") != std::string::npos)
            throw UsageError("--publish sends to the one --topic given, which must have no wildcard");
        options.publish = true;
        options.text = cl.value("--publish");
    }
    installInterruptHandlers();
    const auto r = mqtt::checkBroker(
        config, options, [](const std::string& line) { std::cout << line << "\n" << std::flush; },
        [](const std::string& text) { std::cerr << "mqtt check: " << text << "\n"; }, [] { return interrupted(); });
    std::cerr << "mqtt check: heard " << r.heard << " message(s)\n";
    std::string b;
    armadillo::core::appendJsonString(b, r.broker);
    std::cout << "{\"connected\":true,\"broker\":" << b << ",\"messages\":" << r.heard << ",\"connects\":" << r.connects << "}\n";
    return 0;
}

} // namespace

int runMqtt(const Arguments& args)
{
    return guarded("mqtt", [&] {
        auto options = mqttBrokerOptionSpecs();
        options.push_back({"--broker", "HOST[:PORT]", "the broker to check (as --mqtt)"});
        options.push_back({"--topic", "TOPIC", "subscribe to this topic (wildcards allowed; repeatable; default '#')"});
        options.push_back({"--seconds", "N", "listen this long once connected (default 5; 0 = only connect)"});
        options.push_back({"--count", "N", "stop after N messages"});
        options.push_back({"--timeout", "S", "give up connecting after S seconds (default 5): exit 4"});
        options.push_back({"--publish", "TEXT", "once subscribed, publish TEXT to the --topic (a round trip through the broker)"});
        CommandLine cl("mqtt", "check --broker HOST[:PORT] [--topic T]... [--seconds N] [--publish TEXT]",
                       "MQTT (docs/MQTT.md). `check` connects to the broker, subscribes and prints each message it hears\n"
                       "as a JSON line on stdout (topic, bytes, retained, text), then a summary line. Exit 4 when no\n"
                       "connection is made within --timeout, naming the cause.",
                       options);
        if (args.empty() || args[0] == "--help" || args[0] == "-h") {
            cl.parse({"--help"});
            return args.empty() ? int(core::kExitUsage) : 0;
        }
        if (args[0] != "check") throw UsageError("unknown action '" + args[0] + "' (check)");
        if (!cl.parse(Arguments(args.begin() + 1, args.end()))) return 0;
        if (cl.has("--broker") && cl.has("--mqtt")) throw UsageError("--broker and --mqtt say the same: give one");
        return check(cl);
    });
}

} // namespace armadillo::cli
