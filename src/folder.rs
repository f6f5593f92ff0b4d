//! A render folder's files that one command writes and another reads, by name: the video
//! (`video` writes it, `report` shows it). The renderer's own files are named in
//! [`output`](crate::output) (`output::record::SETTINGS_FILE`, `output::names::FrameNames`).

/// The video's file name in a render folder.
pub const VIDEO_FILE: &str = "video.mp4";
