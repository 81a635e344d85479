//! Copying MCAP messages from one file into another, channels matched by topic (chunk files into
//! `trajectories.mcap`, shards' files into a merged one).

use std::collections::HashMap;
use std::io::{Seek, Write};

/// Maps channels of copied MCAP messages onto a writer's channels (by topic).
#[derive(Default)]
pub struct ChannelMap {
    ids: HashMap<String, u16>,
}

impl ChannelMap {
    /// Copy one message into `w`, adding its schema and channel on first sight.
    pub fn copy<W: Write + Seek>(
        &mut self,
        w: &mut mcap::Writer<W>,
        m: &mcap::Message,
    ) -> mcap::McapResult<()> {
        let id = match self.ids.get(&m.channel.topic) {
            Some(id) => *id,
            None => {
                let schema_id = match &m.channel.schema {
                    Some(s) => w.add_schema(&s.name, &s.encoding, &s.data)?,
                    None => 0,
                };
                let id = w.add_channel(
                    schema_id,
                    &m.channel.topic,
                    &m.channel.message_encoding,
                    &m.channel.metadata,
                )?;
                self.ids.insert(m.channel.topic.clone(), id);
                id
            }
        };
        let header = mcap::records::MessageHeader {
            channel_id: id,
            sequence: m.sequence,
            log_time: m.log_time,
            publish_time: m.publish_time,
        };
        w.write_to_known_channel(&header, &m.data)
    }
}
