#!/usr/bin/python3
"""One MQTT 5 request to the bridge (SPEC §15), as a fleet's application makes it with
paho-mqtt (Debian's python3-paho-mqtt): subscribe RESPONSE_TOPIC, publish PAYLOAD on
TOPIC with Response Topic and Correlation Data, wait for the answer.

  mqtt5_request.py PORT TOPIC PAYLOAD RESPONSE_TOPIC CORRELATION_HEX [--no-properties]
                   [--answer-on TOPIC]

PAYLOAD "@FILE" publishes FILE's bytes (a whole config on config/set).

Prints "answer: <payload>" and "correlation: <hex of its Correlation Data, or none>" of
the first message on RESPONSE_TOPIC, or "error: <reason>" after 5 s. --no-properties
publishes the command without either property (a plain command answered on set/result;
the script then waits on RESPONSE_TOPIC all the same, so give it that). --answer-on
waits for the answer on TOPIC instead (where the bridge answers when it refuses
RESPONSE_TOPIC), and then also prints "on RESPONSE_TOPIC: <n> with the correlation data":
how many messages came there carrying it before the answer (the bridge answers once).

Debian's python3 by its path: python3-paho-mqtt is installed for it, not for another
python3 first on PATH.
"""
import sys
import threading

import paho.mqtt.client as mqtt
from paho.mqtt.packettypes import PacketTypes
from paho.mqtt.properties import Properties


def main():
    port, topic, payload, response_topic, correlation_hex = sys.argv[1:6]
    if payload.startswith("@"):
        with open(payload[1:], "rb") as sent:
            payload = sent.read()
    options = sys.argv[6:]
    with_properties = "--no-properties" not in options
    answer_topic = options[options.index("--answer-on") + 1] if "--answer-on" in options else response_topic
    correlation = bytes.fromhex(correlation_hex)
    misdirected = []
    subscribed = threading.Event()
    answered = threading.Event()
    answer = {}

    client = mqtt.Client(client_id="fleet-app", protocol=mqtt.MQTTv5)

    def on_connect(client, userdata, flags, reason_code, properties):
        topics = {response_topic, answer_topic}
        client.subscribe([(topic, 1) for topic in sorted(topics)])

    def on_subscribe(client, userdata, mid, reason_codes, properties):
        subscribed.set()

    def on_message(client, userdata, message):
        if answered.is_set():
            return
        data = getattr(message.properties, "CorrelationData", None)
        if message.topic != answer_topic:
            if data == correlation:
                misdirected.append(message.topic)
            return
        answer["payload"] = message.payload.decode(errors="replace")
        answer["correlation"] = data.hex() if data is not None else "none"
        answered.set()

    client.on_connect = on_connect
    client.on_subscribe = on_subscribe
    client.on_message = on_message
    client.connect("127.0.0.1", int(port))
    client.loop_start()
    try:
        if not subscribed.wait(5):
            print("error: not subscribed")
            return 1
        properties = Properties(PacketTypes.PUBLISH)
        if with_properties:
            properties.ResponseTopic = response_topic
            properties.CorrelationData = correlation
        client.publish(topic, payload, qos=1, properties=properties)
        if not answered.wait(5):
            print("error: no answer on " + answer_topic)
            return 1
        print("answer: " + answer["payload"])
        print("correlation: " + answer["correlation"])
        if answer_topic != response_topic:
            print("on %s: %d with the correlation data" % (response_topic, len(misdirected)))
        return 0
    finally:
        client.loop_stop()
        client.disconnect()


if __name__ == "__main__":
    sys.exit(main())
