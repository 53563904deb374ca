//! [`FileFlash`]: the two flash sectors of the non-volatile store in a file (`--nv-file`),
//! each erase or program written through to the file and synced, as on real flash; and
//! [`shared`], the one store of the process.

use std::fs::{File, OpenOptions};
use std::io::Read;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use std::cell::{OnceCell, RefCell};

use enip_stack::nv::{
    AbStore, Flash, FlashError, RamFlash, SharedStore, BASE_IMAGE_SIZE, IMAGE_SIZE, MAX_WRITE_SIZE,
};

/// Bytes of one sector in the file.
pub const SECTOR: usize = MAX_WRITE_SIZE + IMAGE_SIZE;
/// Bytes of one sector in the file of a build without CIP Security (the stack's
/// `cip-security` feature makes a copy larger): such a file is carried over, its copies
/// being the same, and rewritten at the larger size.
const BASE_SECTOR: usize = MAX_WRITE_SIZE + BASE_IMAGE_SIZE;

/// The store of a host adapter: in a file, or in RAM (lost at exit).
pub type HostStore = AbStore<HostFlash>;

/// The flash of a host adapter: a file (`--nv-file`) or RAM.
pub enum HostFlash {
    /// Sectors in a file.
    File(FileFlash),
    /// Sectors in RAM.
    Ram(RamFlash<SECTOR>),
}

/// Two sectors of [`SECTOR`] bytes, kept in RAM and written through to a file.
pub struct FileFlash {
    ram: RamFlash<SECTOR>,
    file: File,
    path: PathBuf,
}

impl FileFlash {
    /// Opens (or creates, erased) the file at `path`.
    pub fn open(path: &Path) -> Result<Self, String> {
        let err = |e: std::io::Error| format!("--nv-file {}: {e}", path.display());
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(err)?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes).map_err(err)?;
        let mut sectors = [[0xFF; SECTOR]; 2];
        let mut rewrite = bytes.is_empty();
        match bytes.len() {
            0 => {}
            n if n == 2 * SECTOR => {
                for (s, chunk) in sectors.iter_mut().zip(bytes.chunks(SECTOR)) {
                    s.copy_from_slice(chunk);
                }
            }
            n if BASE_SECTOR < SECTOR && n == 2 * BASE_SECTOR => {
                for (s, chunk) in sectors.iter_mut().zip(bytes.chunks(BASE_SECTOR)) {
                    if let Some(start) = s.get_mut(..BASE_SECTOR) {
                        start.copy_from_slice(chunk);
                    }
                }
                log::info!(
                    "--nv-file {}: a store of {n} bytes, rewritten at {}",
                    path.display(),
                    2 * SECTOR
                );
                rewrite = true;
            }
            n => {
                return Err(format!(
                    "--nv-file {}: {n} bytes, not a store of {} (remove it to start afresh)",
                    path.display(),
                    2 * SECTOR
                ))
            }
        }
        let mut flash = FileFlash {
            ram: RamFlash::from_sectors(sectors),
            file,
            path: path.into(),
        };
        if rewrite {
            flash
                .sync(0, 0, SECTOR)
                .map_err(|_| "cannot write".to_string())?;
            flash
                .sync(1, 0, SECTOR)
                .map_err(|_| "cannot write".to_string())?;
        }
        Ok(flash)
    }

    /// Writes `len` bytes of `sector` from `offset` to the file and syncs it.
    fn sync(&mut self, sector: u8, offset: usize, len: usize) -> Result<(), FlashError> {
        let start = usize::from(sector) * SECTOR + offset;
        let bytes = self
            .ram
            .sectors()
            .get(usize::from(sector))
            .and_then(|s| s.get(offset..offset + len))
            .ok_or(FlashError)?;
        let done = self
            .file
            .write_all_at(bytes, start as u64)
            .and_then(|()| self.file.sync_data());
        done.map_err(|e| {
            log::error!("--nv-file {}: {e}", self.path.display());
            FlashError
        })
    }
}

impl Flash for FileFlash {
    const SECTOR_SIZE: usize = SECTOR;
    const WRITE_SIZE: usize = <RamFlash<SECTOR> as Flash>::WRITE_SIZE;
    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        self.ram.read(sector, offset, buf)
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        self.ram.erase(sector)?;
        self.sync(sector, 0, SECTOR)
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        self.ram.program(sector, offset, data)?;
        self.sync(sector, offset, data.len())
    }
}

impl Flash for HostFlash {
    const SECTOR_SIZE: usize = SECTOR;
    const WRITE_SIZE: usize = <RamFlash<SECTOR> as Flash>::WRITE_SIZE;
    fn read(&mut self, sector: u8, offset: usize, buf: &mut [u8]) -> Result<(), FlashError> {
        match self {
            HostFlash::File(f) => f.read(sector, offset, buf),
            HostFlash::Ram(f) => f.read(sector, offset, buf),
        }
    }
    fn erase(&mut self, sector: u8) -> Result<(), FlashError> {
        match self {
            HostFlash::File(f) => f.erase(sector),
            HostFlash::Ram(f) => f.erase(sector),
        }
    }
    fn program(&mut self, sector: u8, offset: usize, data: &[u8]) -> Result<(), FlashError> {
        match self {
            HostFlash::File(f) => f.program(sector, offset, data),
            HostFlash::Ram(f) => f.program(sector, offset, data),
        }
    }
}

/// The store `--nv-file` names (or one in RAM), opened on the first call and shared by every
/// later one: the adapter (TCP/IP settings) and the device profile (its saved settings) keep
/// their records in the one store, from the one thread that runs them.
pub fn shared(path: Option<&Path>) -> Result<SharedStore, String> {
    thread_local! {
        static STORE: OnceCell<SharedStore> = const { OnceCell::new() };
    }
    STORE.with(|cell| {
        if let Some(store) = cell.get() {
            return Ok(*store);
        }
        let store = own(path)?;
        Ok(*cell.get_or_init(|| store))
    })
}

/// A store of its own at `path` (or in RAM), for one device of several: opened on every
/// call, kept for the life of the process.
pub fn own(path: Option<&Path>) -> Result<SharedStore, String> {
    let store: &'static RefCell<HostStore> = Box::leak(Box::new(RefCell::new(open(path)?)));
    Ok(SharedStore::new(store))
}

/// The store `--nv-file` names, or one in RAM.
pub fn open(path: Option<&Path>) -> Result<HostStore, String> {
    let flash = match path {
        Some(p) => HostFlash::File(FileFlash::open(p)?),
        None => HostFlash::Ram(RamFlash::new()),
    };
    Ok(AbStore::mount(flash))
}

#[cfg(test)]
mod tests {
    use enip_stack::nv::NvStore;

    #[test]
    fn a_file_keeps_the_records() {
        let path = std::env::temp_dir().join(format!("enip-nv-test-{}", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let mut store = super::open(Some(&path)).unwrap();
        store.write(1, b"kept").unwrap();
        store.write(1, b"newer").unwrap();
        drop(store);
        let mut store = super::open(Some(&path)).unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(store.read(1, &mut buf), Ok(Some(5)));
        assert_eq!(&buf[..5], b"newer");
        std::fs::write(&path, b"short").unwrap();
        assert!(super::open(Some(&path)).is_err());
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn a_file_of_a_build_without_cip_security_is_carried_over() {
        use super::{BASE_SECTOR, SECTOR};
        if BASE_SECTOR == SECTOR {
            return;
        }
        let path = std::env::temp_dir().join(format!("enip-nv-base-{}", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let mut store = super::open(Some(&path)).unwrap();
        store.write(1, b"older").unwrap();
        store.write(1, b"kept").unwrap();
        drop(store);
        // The same copies in the shorter sectors of a build without the feature.
        let bytes = std::fs::read(&path).unwrap();
        let base: Vec<u8> = bytes
            .chunks(SECTOR)
            .flat_map(|s| s[..BASE_SECTOR].to_vec())
            .collect();
        std::fs::write(&path, &base).unwrap();
        let mut store = super::open(Some(&path)).unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(store.read(1, &mut buf), Ok(Some(4)));
        assert_eq!(&buf[..4], b"kept");
        assert_eq!(std::fs::metadata(&path).unwrap().len(), 2 * SECTOR as u64);
        drop(store);
        let mut store = super::open(Some(&path)).unwrap();
        assert_eq!(store.read(1, &mut buf), Ok(Some(4)));
        let _ = std::fs::remove_file(&path);
    }
}
