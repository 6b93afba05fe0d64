// A scancrew recording read by @mcap/core, the MCAP library of Foxglove's tools
// (docs/recording.md): once with McapIndexedReader (footer, summary, chunk and message
// indexes, CRCs) and once with McapStreamReader (the records in file order), zstd chunks
// decompressed by fzstd. Checks the header's profile; that every channel has its schema and
// that scancrew channels carry scancrew-codec schemas of their format version; that the
// statistics match the summary and the messages read (per channel); that both readers see
// the same channels and messages; and that log times never decrease within a channel.
// Foxglove channels ("json" messages, "jsonschema" schemas named foxglove.*): every message
// parses as JSON and has the top-level fields its schema requires; with --foxglove, at least
// one such channel must carry messages. Exits 0 printing "read_mcap: ok ...", else 1 with why.
//
//   node web/tests/read_mcap.mjs FILE.mcap [--foxglove]
import { open, readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { decompress } from "fzstd";

const decompressHandlers = {
  zstd: (data, size) => decompress(data, new Uint8Array(Number(size))),
};

function fail(message) {
  console.log(`read_mcap: FAILED: ${message}`);
  process.exit(1);
}

function check(condition, message) {
  if (!condition) fail(message);
}

// Counts messages per channel and checks log times and sequence numbers within each.
function tally(messages, what) {
  const counts = new Map();
  const last = new Map();
  for (const m of messages) {
    counts.set(m.channelId, (counts.get(m.channelId) ?? 0n) + 1n);
    const prev = last.get(m.channelId);
    if (prev) {
      check(m.logTime >= prev.logTime,
        `${what}: channel ${m.channelId}: log time ${m.logTime} after ${prev.logTime}`);
      check(m.sequence === prev.sequence + 1,
        `${what}: channel ${m.channelId}: sequence ${m.sequence} after ${prev.sequence}`);
    }
    last.set(m.channelId, m);
  }
  return counts;
}

function checkSchemas(channels, schemas, what) {
  for (const channel of channels.values()) {
    check(channel.schemaId !== 0 && schemas.has(channel.schemaId),
      `${what}: channel ${channel.topic} has no schema`);
    const schema = schemas.get(channel.schemaId);
    if (channel.messageEncoding === "json") {
      check(schema.encoding === "jsonschema" && schema.name.startsWith("foxglove."),
        `${what}: channel ${channel.topic}: json with schema ${schema.name} (${schema.encoding})`);
      continue;
    }
    if (channel.messageEncoding !== "scancrew") continue;
    const version = channel.metadata.get("format_version");
    check(version !== undefined, `${what}: channel ${channel.topic} has no format_version`);
    check(schema.encoding === "scancrew-codec",
      `${what}: channel ${channel.topic}: schema encoding ${schema.encoding}`);
    check(schema.name.startsWith("scancrew/"), `${what}: schema name ${schema.name}`);
    const text = new TextDecoder().decode(schema.data);
    check(text.includes(`type: ${schema.name}\n`) && text.includes(`format_version: ${version}\n`),
      `${what}: schema ${schema.name}: data does not name its type and version: ${text}`);
  }
}

// Each json message parses and has its schema's required top-level fields; the number of
// json messages.
function checkJson(messages, channels, schemas) {
  const required = new Map();
  for (const [id, channel] of channels) {
    if (channel.messageEncoding !== "json") continue;
    const schema = JSON.parse(new TextDecoder().decode(schemas.get(channel.schemaId).data));
    required.set(id, schema.required ?? []);
  }
  let n = 0;
  for (const m of messages) {
    const fields = required.get(m.channelId);
    if (!fields) continue;
    const topic = channels.get(m.channelId).topic;
    let value;
    try {
      value = JSON.parse(new TextDecoder().decode(m.data));
    } catch (e) {
      fail(`${topic}: a message is not JSON: ${e.message}`);
    }
    for (const f of fields) check(f in value, `${topic}: a message lacks '${f}'`);
    n += 1;
  }
  return n;
}

async function readIndexed(path) {
  const file = await open(path, "r");
  try {
    const readable = {
      size: async () => BigInt((await file.stat()).size),
      read: async (offset, size) => {
        const buffer = new Uint8Array(Number(size));
        const { bytesRead } = await file.read(buffer, 0, buffer.length, Number(offset));
        check(bytesRead === buffer.length, `short read at ${offset}`);
        return buffer;
      },
    };
    const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
    const messages = [];
    for await (const m of reader.readMessages()) messages.push(m);
    return { reader, messages };
  } finally {
    await file.close();
  }
}

function readStreamed(bytes) {
  const stream = new McapStreamReader({ decompressHandlers });
  stream.append(bytes);
  const out = { header: undefined, channels: new Map(), schemas: new Map(), messages: [] };
  for (let record; (record = stream.nextRecord());) {
    if (record.type === "Header") out.header = record;
    else if (record.type === "Schema") out.schemas.set(record.id, record);
    else if (record.type === "Channel") out.channels.set(record.id, record);
    else if (record.type === "Message") out.messages.push(record);
  }
  check(stream.done(), "stream: the file does not end with a footer and the magic");
  return out;
}

async function main() {
  const path = process.argv[2];
  if (!path) fail("usage: node read_mcap.mjs FILE.mcap");

  const { reader, messages } = await readIndexed(path);
  check(reader.header.profile === "scancrew", `profile '${reader.header.profile}'`);
  const stats = reader.statistics;
  check(stats !== undefined, "no Statistics record in the summary");
  check(messages.length > 0, "no messages");
  check(stats.messageCount === BigInt(messages.length),
    `statistics: ${stats.messageCount} messages, ${messages.length} read`);
  check(stats.channelCount === reader.channelsById.size, "statistics: channel count");
  check(stats.schemaCount === reader.schemasById.size, "statistics: schema count");
  check(stats.chunkCount === reader.chunkIndexes.length, "statistics: chunk count");
  check(reader.chunkIndexes.every((c) => c.compression === "zstd"), "a chunk not in zstd");
  checkSchemas(reader.channelsById, reader.schemasById, "indexed");
  const indexedCounts = tally(messages, "indexed");
  for (const [id, channel] of reader.channelsById) {
    const expected = stats.channelMessageCounts.get(id) ?? 0n;
    const read = indexedCounts.get(id) ?? 0n;
    check(expected === read, `${channel.topic}: statistics say ${expected} messages, read ${read}`);
  }
  for (const m of messages)
    check(m.logTime >= stats.messageStartTime && m.logTime <= stats.messageEndTime,
      `message at ${m.logTime} outside the statistics' time range`);

  const streamed = readStreamed(await readFile(path));
  check(streamed.header?.profile === "scancrew", "stream: no scancrew Header");
  check(streamed.channels.size === reader.channelsById.size, "stream: another channel count");
  for (const [id, channel] of reader.channelsById)
    check(streamed.channels.get(id)?.topic === channel.topic, `stream: channel ${id} differs`);
  checkSchemas(streamed.channels, streamed.schemas, "stream");
  check(streamed.messages.length === messages.length,
    `stream: ${streamed.messages.length} messages, indexed ${messages.length}`);
  const streamedCounts = tally(streamed.messages, "stream");
  for (const [id, n] of indexedCounts)
    check(streamedCounts.get(id) === n, `stream: channel ${id}: another message count`);

  const jsonMessages = checkJson(messages, reader.channelsById, reader.schemasById);
  if (process.argv.includes("--foxglove"))
    check(jsonMessages > 0, "--foxglove: no message on a Foxglove (json) channel");

  const topics = [...reader.channelsById.values()]
    .map((c) => `${c.topic} ${indexedCounts.get(c.id) ?? 0n}`)
    .join(", ");
  console.log(`read_mcap: ok: ${messages.length} messages in ${stats.chunkCount} chunks; ${topics}`);
}

main().catch((e) => fail(e?.stack ?? String(e)));
