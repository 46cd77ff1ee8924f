//! The loader thread: a [`ChunkHeightSource`] over a [`PyramidFile`]. Requests go to one
//! `std::thread` over a channel, in the order made; it reads each chunk with one positioned read
//! and sends the heights back with the time from the request to the read's end. `take` waits on
//! the answers, keeping those that come first for later. Not here: when a chunk counts as
//! available (the core's loading model decides), caching (the core's resident set holds the
//! heights), read-ahead.

use super::PyramidFile;
use crate::sim::algorithm::chunked::{ChunkHeightSource, ChunkId, ChunkRead};
use std::collections::HashMap;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;
use std::time::Instant;

/// A pyramid read on a loader thread.
pub struct PyramidLoader {
    requests: Option<Sender<(ChunkId, Instant)>>,
    answers: Receiver<(ChunkId, Result<ChunkRead, String>)>,
    /// Answers received before they were taken.
    early: HashMap<ChunkId, Result<ChunkRead, String>>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for PyramidLoader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PyramidLoader")
            .field("early", &self.early.len())
            .finish()
    }
}

impl PyramidLoader {
    /// Starts the loader thread over `pyramid`.
    pub fn start(pyramid: PyramidFile) -> PyramidLoader {
        let (requests, incoming) = channel::<(ChunkId, Instant)>();
        let (outgoing, answers) = channel();
        let thread = std::thread::Builder::new()
            .name("pyramid-loader".into())
            .spawn(move || {
                let mut heights = Vec::new();
                for (id, requested) in incoming {
                    let read = pyramid
                        .read_heights(id, &mut heights)
                        .map(|()| ChunkRead {
                            heights: heights.clone(),
                            latency_ns: requested.elapsed().as_nanos() as u64,
                        })
                        .map_err(|error| error.to_string());
                    if outgoing.send((id, read)).is_err() {
                        return; // Nobody is waiting any more.
                    }
                }
            })
            .expect("the loader thread starts");
        PyramidLoader {
            requests: Some(requests),
            answers,
            early: HashMap::new(),
            thread: Some(thread),
        }
    }
}

impl ChunkHeightSource for PyramidLoader {
    fn request(&mut self, id: ChunkId) {
        if let Some(requests) = &self.requests {
            // A send fails only when the thread has gone; `take` then says so.
            let _ = requests.send((id, Instant::now()));
        }
    }

    fn take(&mut self, id: ChunkId) -> Result<ChunkRead, String> {
        loop {
            if let Some(read) = self.early.remove(&id) {
                return read;
            }
            let (answered, read) = self
                .answers
                .recv()
                .map_err(|_| format!("the loader thread stopped before chunk {id:?} was read"))?;
            self.early.insert(answered, read);
        }
    }
}

impl Drop for PyramidLoader {
    fn drop(&mut self) {
        self.requests = None; // Closes the channel: the thread's loop ends.
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
