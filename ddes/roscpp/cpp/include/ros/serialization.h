// ddes roscpp: ROS 1 wire serialization (roscpp_serialization's API).
//
// ros::serialization::Serializer<T> writes, reads and sizes one T (write(stream, t),
// read(stream, t), serializedLength(t)); serialize(stream, t), deserialize(stream, t) and
// serializationLength(t) dispatch to it.  Built in: the primitives (little-endian, as the host
// and the wire are), bool (one byte), std::string (u32 length + bytes), ros::Time and
// ros::Duration (two 32-bit words), std::vector<T> (u32 count + elements; memcpy for simple
// T), std::vector<bool> (one byte each), boost::array<T, N> and std::array<T, N> (N elements,
// no count).  A generated message specialises Serializer with its fields in order
// (ROS_DECLARE_ALLINONE_SERIALIZER).
//
// OStream writes into a buffer, IStream reads from one, LStream only counts bytes.  Reading
// (or writing) past the end throws StreamOverrunException; so does a sequence whose count
// promises more elements than the bytes left could hold, before anything is allocated.
#ifndef ROSCPP_SERIALIZATION_H
#define ROSCPP_SERIALIZATION_H

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include <boost/array.hpp>
#include <boost/shared_array.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/builtin_message_traits.h>
#include <ros/exception.h>
#include <ros/macros.h>
#include <ros/message_traits.h>
#include <ros/serialized_message.h>
#include <ros/time.h>
#include <ros/types.h>

#define ROS_NEW_SERIALIZATION_API 1

/// In a Serializer specialisation that defines
///   template<typename Stream, typename T> inline static void allInOne(Stream& stream, T t)
/// (stream.next() on each field in order), defines write, read and serializedLength from it.
#define ROS_DECLARE_ALLINONE_SERIALIZER \
  template <typename Stream, typename T> \
  inline static void write(Stream& stream, const T& t) \
  { \
    allInOne<Stream, const T&>(stream, t); \
  } \
  \
  template <typename Stream, typename T> \
  inline static void read(Stream& stream, T& t) \
  { \
    allInOne<Stream, T&>(stream, t); \
  } \
  \
  template <typename T> \
  inline static uint32_t serializedLength(const T& t) \
  { \
    ::ros::serialization::LStream stream; \
    allInOne< ::ros::serialization::LStream, const T&>(stream, t); \
    return stream.getLength(); \
  }

namespace ros
{
namespace serialization
{
namespace mt = message_traits;

/// Reading or writing past the end of a stream's buffer.
class StreamOverrunException : public ros::Exception
{
public:
  StreamOverrunException(const std::string& what) : Exception(what) {}
};

[[noreturn]] inline void throwStreamOverrun()
{
  throw StreamOverrunException("Buffer Overrun");
}

namespace detail
{
template <typename T> struct DependentFalse : std::false_type {};
}  // namespace detail

/// How one T goes on the wire.  This primary template has no implementation: a type is
/// serializable only through a specialisation (built in below, or generated).
template <typename T>
struct Serializer
{
  static_assert(detail::DependentFalse<T>::value,
                "ros::serialization::Serializer<T> is not specialised for this type: it is not a "
                "ROS message (include its generated header) or a built-in field type");
};

template <typename T, typename Stream>
inline void serialize(Stream& stream, const T& t)
{
  Serializer<T>::write(stream, t);
}

template <typename T, typename Stream>
inline void deserialize(Stream& stream, T& t)
{
  Serializer<T>::read(stream, t);
}

template <typename T>
inline uint32_t serializationLength(const T& t)
{
  return Serializer<T>::serializedLength(t);
}

#define ROS_CREATE_SIMPLE_SERIALIZER(Type) \
  template <> struct Serializer<Type> \
  { \
    template <typename Stream> inline static void write(Stream& stream, const Type v) \
    { \
      std::memcpy(stream.advance(sizeof(v)), &v, sizeof(v)); \
    } \
    template <typename Stream> inline static void read(Stream& stream, Type& v) \
    { \
      std::memcpy(&v, stream.advance(sizeof(v)), sizeof(v)); \
    } \
    inline static uint32_t serializedLength(const Type&) { return sizeof(Type); } \
  };

ROS_CREATE_SIMPLE_SERIALIZER(uint8_t)
ROS_CREATE_SIMPLE_SERIALIZER(int8_t)
ROS_CREATE_SIMPLE_SERIALIZER(uint16_t)
ROS_CREATE_SIMPLE_SERIALIZER(int16_t)
ROS_CREATE_SIMPLE_SERIALIZER(uint32_t)
ROS_CREATE_SIMPLE_SERIALIZER(int32_t)
ROS_CREATE_SIMPLE_SERIALIZER(uint64_t)
ROS_CREATE_SIMPLE_SERIALIZER(int64_t)
ROS_CREATE_SIMPLE_SERIALIZER(float)
ROS_CREATE_SIMPLE_SERIALIZER(double)

/// bool: one byte, 0 or 1 (any non-zero byte reads as true).
template <>
struct Serializer<bool>
{
  template <typename Stream>
  inline static void write(Stream& stream, const bool v)
  {
    const uint8_t b = v ? 1 : 0;
    std::memcpy(stream.advance(1), &b, 1);
  }
  template <typename Stream>
  inline static void read(Stream& stream, bool& v)
  {
    uint8_t b = 0;
    std::memcpy(&b, stream.advance(1), 1);
    v = b != 0;
  }
  inline static uint32_t serializedLength(bool) { return 1; }
};

/// A string: u32 byte length, then the bytes (no terminator).
template <class ContainerAllocator>
struct Serializer<std::basic_string<char, std::char_traits<char>, ContainerAllocator> >
{
  typedef std::basic_string<char, std::char_traits<char>, ContainerAllocator> StringType;

  template <typename Stream>
  inline static void write(Stream& stream, const StringType& str)
  {
    const uint32_t len = static_cast<uint32_t>(str.size());
    stream.next(len);
    if (len > 0)
      std::memcpy(stream.advance(len), str.data(), len);
  }
  template <typename Stream>
  inline static void read(Stream& stream, StringType& str)
  {
    uint32_t len = 0;
    stream.next(len);
    if (len > 0)
      str.assign(reinterpret_cast<const char*>(stream.advance(len)), len);
    else
      str.clear();
  }
  inline static uint32_t serializedLength(const StringType& str)
  {
    return 4 + static_cast<uint32_t>(str.size());
  }
};

/// ros::Time and ros::Duration: sec then nsec, 32 bits each.
template <>
struct Serializer<ros::Time>
{
  template <typename Stream>
  inline static void write(Stream& stream, const ros::Time& v)
  {
    stream.next(v.sec);
    stream.next(v.nsec);
  }
  template <typename Stream>
  inline static void read(Stream& stream, ros::Time& v)
  {
    stream.next(v.sec);
    stream.next(v.nsec);
  }
  inline static uint32_t serializedLength(const ros::Time&) { return 8; }
};

template <>
struct Serializer<ros::Duration>
{
  template <typename Stream>
  inline static void write(Stream& stream, const ros::Duration& v)
  {
    stream.next(v.sec);
    stream.next(v.nsec);
  }
  template <typename Stream>
  inline static void read(Stream& stream, ros::Duration& v)
  {
    stream.next(v.sec);
    stream.next(v.nsec);
  }
  inline static uint32_t serializedLength(const ros::Duration&) { return 8; }
};

namespace detail
{
// Bytes left to read, for streams that know (IStream); LStream/OStream-like ones say "plenty".
template <typename Stream>
inline auto bytesLeft(Stream& stream, int) -> decltype(static_cast<uint64_t>(stream.getLength()))
{
  return static_cast<uint64_t>(stream.getLength());
}
template <typename Stream>
inline uint64_t bytesLeft(Stream&, long)
{
  return std::numeric_limits<uint64_t>::max();
}

// Before a sequence of `count` elements is allocated: can the bytes left hold them?
// Every element takes at least as many bytes as a default-constructed one.
template <typename T, typename Stream>
inline void checkCount(Stream& stream, uint32_t count)
{
  if (count == 0)
    return;
  const uint64_t each = serializationLength(T());
  if (each > 0 && static_cast<uint64_t>(count) * each > bytesLeft(stream, 0))
    throwStreamOverrun();
}

// N elements [first, first + n): memcpy when T is simple, else one by one.
typedef std::integral_constant<int, 0> ByElement;   // sized one by one
typedef std::integral_constant<int, 1> FixedEach;   // every element the same size
typedef std::integral_constant<int, 2> AsMemory;    // simple: memcpy
template <typename T>
struct ElementKind
  : std::integral_constant<int, mt::IsSimple<T>::value ? 2 : mt::IsFixedSize<T>::value ? 1 : 0>
{};

template <typename T, typename Stream>
inline void writeElements(Stream& stream, const T* first, size_t n, AsMemory)
{
  const uint32_t data_len = static_cast<uint32_t>(n * sizeof(T));
  std::memcpy(stream.advance(data_len), first, data_len);
}

template <typename T, typename Stream, typename Kind>
inline void writeElements(Stream& stream, const T* first, size_t n, Kind)
{
  for (size_t i = 0; i < n; ++i)
    stream.next(first[i]);
}

template <typename T, typename Stream>
inline void writeElements(Stream& stream, const T* first, size_t n)
{
  if (n > 0)
    writeElements(stream, first, n, typename std::conditional<ElementKind<T>::value == 2, AsMemory, ByElement>::type());
}

template <typename T, typename Stream>
inline void readElements(Stream& stream, T* first, size_t n, AsMemory)
{
  const uint32_t data_len = static_cast<uint32_t>(n * sizeof(T));
  std::memcpy(static_cast<void*>(first), stream.advance(data_len), data_len);
}

template <typename T, typename Stream, typename Kind>
inline void readElements(Stream& stream, T* first, size_t n, Kind)
{
  for (size_t i = 0; i < n; ++i)
    stream.next(first[i]);
}

template <typename T, typename Stream>
inline void readElements(Stream& stream, T* first, size_t n)
{
  if (n > 0)
    readElements(stream, first, n, typename std::conditional<ElementKind<T>::value == 2, AsMemory, ByElement>::type());
}

template <typename T>
inline uint32_t elementsLength(const T*, size_t n, AsMemory)
{
  return static_cast<uint32_t>(n * sizeof(T));
}

template <typename T>
inline uint32_t elementsLength(const T* first, size_t n, FixedEach)
{
  return static_cast<uint32_t>(n) * serializationLength(first[0]);
}

template <typename T>
inline uint32_t elementsLength(const T* first, size_t n, ByElement)
{
  uint32_t size = 0;
  for (size_t i = 0; i < n; ++i)
    size += serializationLength(first[i]);
  return size;
}

template <typename T>
inline uint32_t elementsLength(const T* first, size_t n)
{
  if (n == 0)
    return 0;
  return elementsLength(first, n, std::integral_constant<int, ElementKind<T>::value>());
}
}  // namespace detail

/// A variable-length array: u32 element count, then the elements.
template <typename T, class ContainerAllocator>
struct VectorSerializer
{
  typedef std::vector<T, ContainerAllocator> VecType;

  template <typename Stream>
  inline static void write(Stream& stream, const VecType& v)
  {
    stream.next(static_cast<uint32_t>(v.size()));
    detail::writeElements(stream, v.data(), v.size());
  }
  template <typename Stream>
  inline static void read(Stream& stream, VecType& v)
  {
    uint32_t len = 0;
    stream.next(len);
    detail::checkCount<T>(stream, len);
    v.resize(len);
    detail::readElements(stream, v.data(), v.size());
  }
  inline static uint32_t serializedLength(const VecType& v)
  {
    return 4 + detail::elementsLength(v.data(), v.size());
  }
};

/// std::vector<bool> (packed in memory): one byte per element on the wire.
template <class ContainerAllocator>
struct VectorSerializer<bool, ContainerAllocator>
{
  typedef std::vector<bool, ContainerAllocator> VecType;

  template <typename Stream>
  inline static void write(Stream& stream, const VecType& v)
  {
    const uint32_t len = static_cast<uint32_t>(v.size());
    stream.next(len);
    if (len == 0)
      return;
    uint8_t* out = stream.advance(len);
    for (uint32_t i = 0; i < len; ++i)
      out[i] = v[i] ? 1 : 0;
  }
  template <typename Stream>
  inline static void read(Stream& stream, VecType& v)
  {
    uint32_t len = 0;
    stream.next(len);
    const uint8_t* in = len > 0 ? stream.advance(len) : 0;
    v.resize(len);
    for (uint32_t i = 0; i < len; ++i)
      v[i] = in[i] != 0;
  }
  inline static uint32_t serializedLength(const VecType& v)
  {
    return 4 + static_cast<uint32_t>(v.size());
  }
};

template <typename T, class ContainerAllocator>
struct Serializer<std::vector<T, ContainerAllocator> > : VectorSerializer<T, ContainerAllocator> {};

/// A fixed-length array (gencpp's boost::array, or std::array): the N elements, no count.
template <typename T, size_t N, class ArrayType>
struct FixedArraySerializer
{
  template <typename Stream>
  inline static void write(Stream& stream, const ArrayType& v)
  {
    detail::writeElements(stream, v.data(), N);
  }
  template <typename Stream>
  inline static void read(Stream& stream, ArrayType& v)
  {
    detail::readElements(stream, v.data(), N);
  }
  inline static uint32_t serializedLength(const ArrayType& v)
  {
    return detail::elementsLength(v.data(), N);
  }
};

template <typename T, size_t N>
struct ArraySerializer : FixedArraySerializer<T, N, boost::array<T, N> >
{
  typedef boost::array<T, N> ArrayType;
};

template <typename T, size_t N>
struct Serializer<boost::array<T, N> > : ArraySerializer<T, N> {};

template <typename T, size_t N>
struct Serializer<std::array<T, N> > : FixedArraySerializer<T, N, std::array<T, N> > {};

namespace stream_types
{
enum StreamType
{
  Input,
  Output,
  Length
};
}  // namespace stream_types
typedef stream_types::StreamType StreamType;

/// A window [data, end) over a buffer the stream does not own.
struct Stream
{
  inline uint8_t* getData() { return data_; }

  /// The next `len` bytes; throws StreamOverrunException if fewer are left.
  ROS_FORCE_INLINE uint8_t* advance(uint32_t len)
  {
    if (len > static_cast<size_t>(end_ - data_))
      throwStreamOverrun();
    uint8_t* old_data = data_;
    data_ += len;
    return old_data;
  }

  /// Bytes left.
  inline uint32_t getLength() { return static_cast<uint32_t>(end_ - data_); }

protected:
  Stream(uint8_t* _data, uint32_t _count) : data_(_data), end_(_data + _count) {}

private:
  uint8_t* data_;
  uint8_t* end_;
};

/// Reads values from a buffer: stream.next(value) or stream >> value.
struct IStream : public Stream
{
  static const StreamType stream_type = stream_types::Input;

  IStream(uint8_t* data, uint32_t count) : Stream(data, count) {}

  template <typename T>
  ROS_FORCE_INLINE void next(T& t)
  {
    deserialize(*this, t);
  }

  template <typename T>
  ROS_FORCE_INLINE IStream& operator>>(T& t)
  {
    deserialize(*this, t);
    return *this;
  }
};

/// Writes values into a buffer: stream.next(value) or stream << value.
struct OStream : public Stream
{
  static const StreamType stream_type = stream_types::Output;

  OStream(uint8_t* data, uint32_t count) : Stream(data, count) {}

  template <typename T>
  ROS_FORCE_INLINE void next(const T& t)
  {
    serialize(*this, t);
  }

  template <typename T>
  ROS_FORCE_INLINE OStream& operator<<(const T& t)
  {
    serialize(*this, t);
    return *this;
  }
};

/// Counts the bytes values would take.
struct LStream
{
  static const StreamType stream_type = stream_types::Length;

  LStream() : count_(0) {}

  template <typename T>
  ROS_FORCE_INLINE void next(const T& t)
  {
    count_ += serializationLength(t);
  }

  ROS_FORCE_INLINE uint32_t advance(uint32_t len)
  {
    uint32_t old = count_;
    count_ += len;
    return old;
  }

  inline uint32_t getLength() { return count_; }

private:
  uint32_t count_;
};

/// The message behind a u32 length (TCPROS's framing); message_start points past the length.
template <typename M>
inline SerializedMessage serializeMessage(const M& message)
{
  SerializedMessage m;
  const uint32_t len = serializationLength(message);
  m.num_bytes = len + 4;
  m.buf.reset(new uint8_t[m.num_bytes]);

  OStream s(m.buf.get(), static_cast<uint32_t>(m.num_bytes));
  serialize(s, static_cast<uint32_t>(m.num_bytes) - 4);
  m.message_start = s.getData();
  serialize(s, message);
  return m;
}

/// A service response as TCPROS frames it: the ok byte, then (if ok) a u32 length and the
/// message, else the message alone (an error string).
template <typename M>
inline SerializedMessage serializeServiceResponse(bool ok, const M& message)
{
  SerializedMessage m;
  const uint32_t len = serializationLength(message);
  if (ok)
  {
    m.num_bytes = len + 5;
    m.buf.reset(new uint8_t[m.num_bytes]);
    OStream s(m.buf.get(), static_cast<uint32_t>(m.num_bytes));
    serialize(s, static_cast<uint8_t>(ok));
    serialize(s, static_cast<uint32_t>(m.num_bytes) - 5);
    serialize(s, message);
  }
  else
  {
    m.num_bytes = len + 1;
    m.buf.reset(new uint8_t[m.num_bytes]);
    OStream s(m.buf.get(), static_cast<uint32_t>(m.num_bytes));
    serialize(s, static_cast<uint8_t>(ok));
    serialize(s, message);
  }
  return m;
}

/// Reads `message` from the bytes of m after message_start.
template <typename M>
inline void deserializeMessage(const SerializedMessage& m, M& message)
{
  IStream s(m.message_start, static_cast<uint32_t>(m.num_bytes - (m.message_start - m.buf.get())));
  deserialize(s, message);
}

// ddes extension: a message's bare wire bytes (no length prefix) and back, as the world's
// protocol carries them (docs/external-nodes.md, PUBLISH/CALLBACK blobs).

/// The message's wire bytes, without TCPROS's length prefix.
template <typename M>
inline std::vector<uint8_t> serializeToBytes(const M& message)
{
  std::vector<uint8_t> bytes(serializationLength(message));
  if (!bytes.empty())
  {
    OStream s(bytes.data(), static_cast<uint32_t>(bytes.size()));
    serialize(s, message);
  }
  return bytes;
}

/// Reads `message` from `size` wire bytes at `data` (bytes past the message are ignored, as
/// roscpp ignores them); throws StreamOverrunException if they end too soon.
template <typename M>
inline void deserializeFromBytes(const uint8_t* data, size_t size, M& message)
{
  if (size > std::numeric_limits<uint32_t>::max())
    throwStreamOverrun();
  IStream s(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
  deserialize(s, message);
}

template <typename M>
inline void deserializeFromBytes(const std::vector<uint8_t>& bytes, M& message)
{
  deserializeFromBytes(bytes.data(), bytes.size(), message);
}

/// What a subscription hands PreDeserialize<M>::notify before it deserializes.
template <typename M>
struct PreDeserializeParams
{
  boost::shared_ptr<M> message;
  boost::shared_ptr<std::map<std::string, std::string> > connection_header;
};

/// Called with the empty message and the connection header before deserialization
/// (a specialisation may use the header; the default does nothing).
template <typename M>
struct PreDeserialize
{
  static void notify(const PreDeserializeParams<M>&) {}
};

}  // namespace serialization
}  // namespace ros

#endif  // ROSCPP_SERIALIZATION_H
