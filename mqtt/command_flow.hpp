#pragma once
// How many MQTT commands may wait for their answer at once (issue 43, finding 6). A command
// that kept a write waits for the state file's fdatasync before it is answered; a client
// that publishes faster than the disk syncs would otherwise pile up commands without
// end, and the loop would spend seconds committing and answering them while a Modbus
// request waits. Once more than `high_water` wait, the client stops taking messages from
// the broker's socket (the broker holds them: its own flow control, QoS 1 included), and
// takes them again once no more than `low_water` wait — a gap, so that it does not switch
// on every answer. Nothing read is ever dropped: a message taken is carried out.
// Pure: the MQTT service tells it what happens and asks it whether to read.

#include <cstddef>

namespace unima::mqtt {

class CommandFlow {
 public:
  struct Bounds {
    std::size_t high_water = 256;  // a few fdatasyncs' worth at the rates the disk takes
    std::size_t low_water = 128;
  };

  CommandFlow() : CommandFlow(Bounds{}) {}
  explicit CommandFlow(Bounds bounds) : bounds_(bounds) {}

  /// A command went into the write path; it waits until answered().
  void taken();
  /// A command taken was answered (its write durable, refused, or never kept).
  void answered();

  /// Whether the client may take more messages from the broker.
  bool reading() const { return reading_; }
  std::size_t waiting() const { return waiting_; }
  const Bounds& bounds() const { return bounds_; }

 private:
  Bounds bounds_;
  std::size_t waiting_ = 0;
  bool reading_ = true;
};

}  // namespace unima::mqtt
