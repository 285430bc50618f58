// The MQTT configuration file (Mqtt/MqttConfig.h parseMqttConfig) and broker addresses.
#include "FuzzTarget.h"
#include "Mqtt/MqttConfig.h"

ARMADILLO_FUZZ_TARGET(mqtt_config)
{
    using namespace armadillo::mqtt;
    const std::string text(armadillo::fuzz::text(data, size));
    try {
        std::string host;
        int port = 0;
        parseBrokerAddress(text, "--mqtt", host, port);
    } catch (const armadillo::core::InputError&) {
    }
    (void)parseMqttConfig(text, "fuzz.json");
}
