#include "smap/core/JsonWriter.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace smap::core
{
JsonValue JsonValue::object()
{
    return JsonValue{};
}

JsonValue JsonValue::array()
{
    JsonValue v;
    v.kind_ = Kind::Array;
    return v;
}

JsonValue JsonValue::number(double d)
{
    JsonValue v;
    v.kind_ = Kind::Number;
    v.number_ = d;
    return v;
}

JsonValue JsonValue::integer(int64_t i)
{
    JsonValue v;
    v.kind_ = Kind::Integer;
    v.integer_ = i;
    return v;
}

JsonValue JsonValue::string(const std::string& s)
{
    JsonValue v;
    v.kind_ = Kind::String;
    v.string_ = s;
    return v;
}

JsonValue JsonValue::boolean(bool b)
{
    JsonValue v;
    v.kind_ = Kind::Boolean;
    v.boolean_ = b;
    return v;
}

JsonValue& JsonValue::set(const std::string& key, JsonValue v)
{
    for (auto& m : members_)
    {
        if (m.first == key)
        {
            m.second = std::move(v);
            return *this;
        }
    }
    members_.emplace_back(key, std::move(v));
    return *this;
}

JsonValue& JsonValue::push(JsonValue v)
{
    items_.push_back(std::move(v));
    return *this;
}

JsonValue* JsonValue::find(const std::string& key)
{
    for (auto& [k, v] : members_)
        if (k == key)
            return &v;
    return nullptr;
}

JsonValue& JsonValue::erase(const std::string& key)
{
    members_.erase(std::remove_if(members_.begin(), members_.end(),
                                  [&key](const auto& m) { return m.first == key; }),
                   members_.end());
    return *this;
}

std::string jsonEscape(const std::string& s)
{
    std::string out;
    out.reserve(s.size() + 2);
    for (const char c : s)
    {
        switch (c)
        {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20)
                {
                    static constexpr char kHex[] = "0123456789abcdef";
                    const auto u = static_cast<unsigned char>(c);
                    out += "\\u00";
                    out += kHex[u >> 4];
                    out += kHex[u & 0xF];
                }
                else
                {
                    out += c;
                }
        }
    }
    return out;
}

std::string JsonValue::dump(int indent) const
{
    std::string out;
    dumpTo(out, indent, 0);
    out += '\n';
    return out;
}

void JsonValue::dumpTo(std::string& out, int indent, int level) const
{
    const std::string pad(static_cast<size_t>(indent * (level + 1)), ' ');
    const std::string padEnd(static_cast<size_t>(indent * level), ' ');
    switch (kind_)
    {
        case Kind::Number:
        {
            if (!std::isfinite(number_))
            {
                out += "null";
                break;
            }
            char buf[64];
            const auto res = std::to_chars(buf, buf + sizeof(buf), number_);
            out.append(buf, res.ptr);
            break;
        }
        case Kind::Integer:
            out += std::to_string(integer_);
            break;
        case Kind::String:
            out += "\"" + jsonEscape(string_) + "\"";
            break;
        case Kind::Boolean:
            out += boolean_ ? "true" : "false";
            break;
        case Kind::Array:
            out += "[";
            for (size_t i = 0; i < items_.size(); i++)
            {
                out += (i ? ",\n" : "\n") + pad;
                items_[i].dumpTo(out, indent, level + 1);
            }
            out += items_.empty() ? "]" : "\n" + padEnd + "]";
            break;
        case Kind::Object:
            out += "{";
            for (size_t i = 0; i < members_.size(); i++)
            {
                out += (i ? ",\n" : "\n") + pad + "\"" + jsonEscape(members_[i].first) + "\": ";
                members_[i].second.dumpTo(out, indent, level + 1);
            }
            out += members_.empty() ? "}" : "\n" + padEnd + "}";
            break;
    }
}
}  // namespace smap::core
