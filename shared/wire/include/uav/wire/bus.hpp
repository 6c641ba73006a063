#pragma once
// The message bus: a small interface over LCM so that the algorithms never see it and tests can
// run on "memq://" (in-process) as well as UDP multicast.
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace uav {

// Decodes one datagram as Msg, the one way every receiver does: false for a datagram that does
// not decode, has bytes left over, or is not exactly what our encoder writes for the message it
// decodes to (LCM's decoder ignores some bytes, the one after each string for instance, so two
// datagrams could carry one message; signatures are checked over the message's encoding, which
// must be the datagram itself). Never throws: a malformed datagram must not take a process down.
template <class Msg>
bool DecodeDatagram(const void* data, size_t size, Msg* msg) {
  if (size > static_cast<size_t>(INT32_MAX)) return false;
  try {
    if (msg->decode(data, 0, static_cast<int>(size)) != static_cast<int>(size)) return false;
    std::vector<uint8_t> bytes(size);
    return msg->encode(bytes.data(), 0, static_cast<int>(size)) == static_cast<int>(size) &&
           std::memcmp(bytes.data(), data, size) == 0;
  } catch (const std::exception&) {
    return false;
  }
}

class Bus {
 public:
  // Throws std::runtime_error naming the URL when LCM cannot start on it.
  explicit Bus(const std::string& url);
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  const std::string& url() const { return url_; }

  template <class Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    lcm_.publish(channel, &msg);
  }

  // Calls `on_message(channel, msg)` for each message on channels matching the regex `pattern`.
  // A message that does not decode as Msg is dropped and counted (DecodeErrors()).
  template <class Msg>
  void Subscribe(const std::string& pattern,
                 std::function<void(const std::string& channel, const Msg&)> on_message) {
    auto handler = std::make_unique<TypedHandler<Msg>>(std::move(on_message), &decode_errors_);
    lcm_.subscribe(pattern, &HandlerBase::Handle, static_cast<HandlerBase*>(handler.get()));
    handlers_.push_back(std::move(handler));
  }

  // Every message on channels matching `pattern`, undecoded (for the event log). LCM queues 30
  // messages per subscription between Handle() calls and drops the rest; a recorder that must
  // keep bursts (a map download's chunks) asks for a deeper queue.
  void SubscribeRaw(const std::string& pattern,
                    std::function<void(const std::string& channel, const lcm::ReceiveBuffer& rbuf)> on_message,
                    int queue_capacity = 30) {
    auto handler = std::make_unique<RawHandler>(std::move(on_message));
    lcm::Subscription* sub = lcm_.subscribe(pattern, &HandlerBase::Handle, static_cast<HandlerBase*>(handler.get()));
    if (sub) sub->setQueueCapacity(queue_capacity);
    handlers_.push_back(std::move(handler));
  }

  // Dispatches messages that arrive within `timeout_ms` (0: only those already queued).
  // Returns the number of messages handled.
  int Handle(int timeout_ms);

  int64_t DecodeErrors() const { return decode_errors_; }

 private:
  struct HandlerBase {
    virtual ~HandlerBase() = default;
    virtual void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) = 0;
  };
  template <class Msg>
  struct TypedHandler : HandlerBase {
    TypedHandler(std::function<void(const std::string&, const Msg&)> f, int64_t* errors)
        : fn(std::move(f)), decode_errors(errors) {}
    void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) override {
      Msg msg;
      if (!DecodeDatagram(rbuf->data, rbuf->data_size, &msg)) {
        ++*decode_errors;
        return;
      }
      fn(channel, msg);
    }
    std::function<void(const std::string&, const Msg&)> fn;
    int64_t* decode_errors;
  };

  struct RawHandler : HandlerBase {
    explicit RawHandler(std::function<void(const std::string&, const lcm::ReceiveBuffer&)> f) : fn(std::move(f)) {}
    void Handle(const lcm::ReceiveBuffer* rbuf, const std::string& channel) override { fn(channel, *rbuf); }
    std::function<void(const std::string&, const lcm::ReceiveBuffer&)> fn;
  };

  std::string url_;
  lcm::LCM lcm_;
  std::vector<std::unique_ptr<HandlerBase>> handlers_;
  int64_t decode_errors_ = 0;
};

}  // namespace uav
