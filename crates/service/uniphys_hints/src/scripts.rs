//! The Lua scripts that make rate limits and slot pools atomic across processes.
//!
//! Both read the clock with `TIME` on the Redis server, so processes with skewed clocks share
//! one notion of now. All times are Unix milliseconds.

/// Token bucket (same arithmetic as [`crate::rate_limit::TokenBucket::take`]).
///
/// KEYS[1] = the bucket's hash; ARGV = capacity (= per minute), tokens wanted, window ms.
/// Returns 0 when the tokens were taken, else the milliseconds to wait (>= 1).
pub(crate) const TOKEN_BUCKET: &str = r"
local capacity = tonumber(ARGV[1])
local wanted = tonumber(ARGV[2])
local window = tonumber(ARGV[3])
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000)
local tokens = tonumber(redis.call('HGET', KEYS[1], 'tokens'))
local updated = tonumber(redis.call('HGET', KEYS[1], 'updated_at_ms'))
if tokens == nil or updated == nil then
  tokens = capacity
  updated = now
end
if now > updated then
  tokens = tokens + (now - updated) * capacity / window
  updated = now
end
if tokens > capacity then
  tokens = capacity
end
local wait = 0
if tokens >= wanted then
  tokens = tokens - wanted
else
  wait = math.ceil((wanted - tokens) * window / capacity)
  if wait < 1 then
    wait = 1
  end
end
redis.call('HSET', KEYS[1], 'tokens', tostring(tokens), 'updated_at_ms', tostring(updated))
redis.call('PEXPIRE', KEYS[1], window * 2)
return wait
";

/// Take or refresh a slot in a pool.
///
/// KEYS[1] = the pool's sorted set (member = holder, score = expiry); ARGV = capacity, holder,
/// ttl ms. Drops expired holders first. A holder already in the pool gets its expiry moved on;
/// a new one gets in when there is room. The key itself expires with its longest-lived holder.
/// Returns 1 when `holder` holds a slot afterwards, else 0.
pub(crate) const TAKE_SLOT: &str = r"
local capacity = tonumber(ARGV[1])
local ttl = tonumber(ARGV[3])
local t = redis.call('TIME')
local now = tonumber(t[1]) * 1000 + math.floor(tonumber(t[2]) / 1000)
redis.call('ZREMRANGEBYSCORE', KEYS[1], '-inf', now)
local held = redis.call('ZSCORE', KEYS[1], ARGV[2])
if held or redis.call('ZCARD', KEYS[1]) < capacity then
  redis.call('ZADD', KEYS[1], now + ttl, ARGV[2])
  if redis.call('PTTL', KEYS[1]) < ttl then
    redis.call('PEXPIRE', KEYS[1], ttl)
  end
  return 1
end
return 0
";
